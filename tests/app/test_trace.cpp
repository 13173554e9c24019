#include <doctest/doctest.h>

#include <cstring>

#include "render/ray_stream.h"
#include "render/trace.h"
#include "scenes/builtin.h"

using namespace trident;

namespace {

bool same_bits(const Hit& a, const Hit& b) {
    return a.triangle == b.triangle && std::memcmp(&a.t, &b.t, sizeof(float)) == 0;
}

/// The structures whose packet traversal the renderer uses; each must match its scalar path.
std::vector<AccelKind> kinds_with_packets() { return built_accel_kinds(); }

}  // namespace

TEST_CASE("packet rendering equals scalar rendering, bit for bit, with partial packets at the image edge") {
    const Scene scene = make_builtin_scene("teapot");
    // 37x23 is no multiple of any packet block: edge packets have inactive lanes.
    const Camera camera(scene.camera, 37, 23);
    for (AccelKind kind : kinds_with_packets()) {
        const AnyAccel accel = AnyAccel::build(kind, scene.mesh);
        const std::vector<Hit> scalar = trace_primary(accel, camera);
        std::size_t hits = 0;
        for (const Hit& h : scalar) hits += h.is_hit();
        CHECK(hits > 0);
        for (SimdWidth width : {SimdWidth::w4, SimdWidth::w8, SimdWidth::w16}) {
            if (!is_runnable(width)) continue;
            CAPTURE(to_string(kind));
            CAPTURE(to_string(width));
            const std::vector<Hit> packed = trace_primary(accel, camera, TriangleTest::watertight, width);
            std::size_t differ = 0;
            for (std::size_t i = 0; i < scalar.size(); ++i) differ += !same_bits(scalar[i], packed[i]);
            CHECK(differ == 0);
        }
    }
}

TEST_CASE("packet occlusion equals scalar occlusion and skips rays with nothing to trace") {
    const Scene scene = make_builtin_scene("teapot");
    const Camera camera(scene.camera, 29, 17);
    const AnyAccel accel = AnyAccel::build(AccelKind::brute, scene.mesh);
    std::vector<Ray> rays;
    for (std::uint32_t y = 0; y < camera.height(); ++y)
        for (std::uint32_t x = 0; x < camera.width(); ++x) {
            Ray ray = camera.primary_ray(x, y);
            if ((x + y) % 5 == 0) ray.tmax = 0.0f;  // nothing to trace: must read as unoccluded
            if ((x + y) % 7 == 0) ray.tmax = 1.0f;  // too short to reach the teapot
            rays.push_back(ray);
        }
    auto occlusion = [&](SimdWidth width) {
        std::vector<std::uint8_t> occluded(rays.size(), 7);
        occlude_stream_parallel(accel, rays, occluded, {width, PacketGrouping::in_order});
        return occluded;
    };
    const std::vector<std::uint8_t> scalar = occlusion(SimdWidth::scalar);
    for (SimdWidth width : {SimdWidth::w4, SimdWidth::w8, SimdWidth::w16}) {
        if (!is_runnable(width)) continue;
        CAPTURE(to_string(width));
        CHECK(occlusion(width) == scalar);
    }
    for (std::size_t i = 0; i < rays.size(); ++i)
        if (!(rays[i].tmax > rays[i].tmin)) CHECK(scalar[i] == 0);
}
