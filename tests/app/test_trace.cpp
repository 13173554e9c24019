#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <immintrin.h>
#include <limits>

#include "render/ray_stream.h"
#include "render/trace.h"
#include "scenes/builtin.h"
#include "support/sanitizer_workload.h"

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

TEST_CASE("under every ISA cap this CPU has, every width it allows gives the scalar hits bit for bit") {
    const Scene scene = make_builtin_scene("teapot");
    // No multiple of any packet block; smaller under the sanitizers (support/sanitizer_workload.h),
    // where the brute force's 6,320 triangles per ray dominate the run.
    const Camera camera(scene.camera, testing::kSanitized ? 19 : 37, testing::kSanitized ? 11 : 23);
    // Secondary rays from the teapot's surface in scattered directions, for the stream kernels.
    std::vector<Ray> rays;
    for (std::uint32_t y = 0; y < camera.height(); ++y)
        for (std::uint32_t x = 0; x < camera.width(); ++x) {
            const Ray primary = camera.primary_ray(x, y);
            const float a = float((x * 7 + y * 13) % 17) - 8.0f, b = float((x * 5 + y * 3) % 11) - 5.0f;
            rays.push_back(
                Ray{primary.origin + primary.dir * (0.8f * float(x + y + 1) / float(camera.width() + camera.height())),
                    {a, b, 1.0f},
                    0.0f,
                    kInfinity});
        }
    auto same_all_bits = [](const std::vector<Hit>& a, const std::vector<Hit>& b) {
        std::size_t differ = 0;
        for (std::size_t i = 0; i < a.size(); ++i)
            differ += !(same_bits(a[i], b[i]) && std::memcmp(&a[i].u, &b[i].u, sizeof(float)) == 0 &&
                        std::memcmp(&a[i].v, &b[i].v, sizeof(float)) == 0);
        return differ;
    };
    const auto saved = isa_cap();
    for (AccelKind kind : kinds_with_packets()) {
        CAPTURE(to_string(kind));
        // The structure and its scalar hits once, uncapped. Under each cap the single rays are traced
        // again: in the portable build they run in the cap's widest kernel file (SingleRayKernels).
        const AnyAccel accel = AnyAccel::build(kind, scene.mesh);
        const std::vector<Hit> scalar = trace_primary(accel, camera);
        std::vector<Hit> scalar_stream(rays.size());
        intersect_stream(accel, rays, scalar_stream, {SimdWidth::scalar});
        std::vector<std::uint8_t> scalar_occluded(rays.size());
        occlude_stream(accel, rays, scalar_occluded, {SimdWidth::scalar});
        for (const IsaLevel cap : {IsaLevel::sse4, IsaLevel::avx2, IsaLevel::avx512}) {
            set_isa_cap(cap);
            CAPTURE(to_string(cap));
            CHECK(same_all_bits(scalar, trace_primary(accel, camera)) == 0);
            std::vector<Hit> capped_stream(rays.size());
            intersect_stream(accel, rays, capped_stream, {SimdWidth::scalar});
            CHECK(same_all_bits(scalar_stream, capped_stream) == 0);
            std::vector<std::uint8_t> capped_occluded(rays.size());
            occlude_stream(accel, rays, capped_occluded, {SimdWidth::scalar});
            CHECK(capped_occluded == scalar_occluded);
            for (SimdWidth width : {SimdWidth::w4, SimdWidth::w8, SimdWidth::w16}) {
                CAPTURE(to_string(width));
                if (!is_compiled_in(width) || !cpu_supports(width)) continue;
                if (!cap_allows(width)) {
                    CHECK_THROWS_WITH_AS(trace_primary(accel, camera, TriangleTest::watertight, width),
                                         doctest::Contains("TRIDENT_ISA"), std::runtime_error);
                    continue;
                }
                CHECK(same_all_bits(scalar, trace_primary(accel, camera, TriangleTest::watertight, width)) == 0);
                std::vector<Hit> stream(rays.size());
                intersect_stream(accel, rays, stream, {width});
                CHECK(same_all_bits(scalar_stream, stream) == 0);
                std::vector<std::uint8_t> occluded(rays.size());
                occlude_stream(accel, rays, occluded, {width});
                CHECK(occluded == scalar_occluded);
            }
            CHECK(lane_count(widest_supported()) <= lane_count(cap == IsaLevel::sse4   ? SimdWidth::w4
                                                               : cap == IsaLevel::avx2 ? SimdWidth::w8
                                                                                       : SimdWidth::w16));
        }
        set_isa_cap(saved);
    }
}

TEST_CASE("ISA levels print as they parse, and nothing else parses") {
    for (const IsaLevel level : {IsaLevel::sse4, IsaLevel::avx2, IsaLevel::avx512})
        CHECK(parse_isa_level(to_string(level)) == level);
    for (const char* bad : {"", "sse2", "AVX2", "avx512bw", "avx-512", "native"}) {
        CAPTURE(bad);
        CHECK_FALSE(parse_isa_level(bad).has_value());
    }
}

TEST_CASE("rays kept in arrays, traced tile by tile, equal single rays in every layout and width") {
    const Scene scene = make_builtin_scene("teapot");
    // 37x23 (21x19 under the sanitizers, where the brute force's 6,320 triangles per ray dominate the
    // run) cuts tiles and packet blocks at the right and bottom edges; rays jittered off the camera's.
    const Camera camera(scene.camera, testing::kSanitized ? 21 : 37, testing::kSanitized ? 19 : 23);
    // A list's rows of rays: more than one, the last one short.
    const std::uint32_t run = testing::kSanitized ? 256 : 512;
    std::vector<Ray> rays;
    std::vector<float> six;  // origin then direction per ray, as numpy's (..., 6) arrays
    std::vector<float> directions;
    for (std::uint32_t y = 0; y < camera.height(); ++y)
        for (std::uint32_t x = 0; x < camera.width(); ++x) {
            Ray ray = camera.primary_ray(x, y);
            ray.dir.x += 0.01f * float((x * 7 + y * 3) % 5);
            rays.push_back(ray);
            six.insert(six.end(), {ray.origin.x, ray.origin.y, ray.origin.z, ray.dir.x, ray.dir.y, ray.dir.z});
            directions.insert(directions.end(), {ray.dir.x, ray.dir.y, ray.dir.z});
        }
    REQUIRE(rays.size() > run);       // the list's rows: more than one
    REQUIRE(rays.size() % run != 0);  // the last one short
    const Vec3f eye = rays[0].origin;
    const float shared_origin[3] = {eye.x, eye.y, eye.z};
    const StridedRays six_float{
        .origins = six.data(), .origin_stride = 6, .directions = six.data() + 3, .direction_stride = 6};
    const StridedRays shared{.origins = shared_origin, .origin_stride = 0, .directions = directions.data()};
    for (AccelKind kind : kinds_with_packets()) {
        const AnyAccel accel = AnyAccel::build(kind, scene.mesh);
        std::vector<Hit> expected(rays.size());
        std::vector<std::uint8_t> expected_occluded(rays.size());
        intersect_stream(accel, rays, expected, {SimdWidth::scalar});
        occlude_stream(accel, rays, expected_occluded, {SimdWidth::scalar});
        std::size_t hits = 0;
        for (const Hit& h : expected) hits += h.is_hit();
        REQUIRE(hits > 0);
        for (SimdWidth width : {SimdWidth::scalar, SimdWidth::w4, SimdWidth::w8, SimdWidth::w16}) {
            if (!is_runnable(width)) continue;
            // An image of rays in 16x16 tiles, and the same rays as a list in rows of `run` runs; the
            // hits written with normal or streaming stores.
            const RayImage streamed{.rays = six_float, .width = camera.width(), .stream_results = true};
            const RayImage streamed_runs{.rays = six_float, .width = run, .runs = true, .stream_results = true};
            for (const auto& [arrays, image] : {std::pair{six_float, RayImage{six_float, camera.width()}},
                                                std::pair{shared, RayImage{shared, camera.width()}},
                                                std::pair{six_float, RayImage{six_float, run, true}},
                                                std::pair{six_float, streamed}, std::pair{six_float, streamed_runs}}) {
                CAPTURE(std::string(to_string(kind)));
                CAPTURE(std::string(to_string(width)));
                CAPTURE(arrays.origin_stride);
                CAPTURE(image.runs);
                CAPTURE(image.stream_results);
                std::vector<Hit> got(rays.size(), Hit{7, 1.0f});
                // Streaming stores need 16-byte aligned results: what operator new gives on x86-64.
                REQUIRE(reinterpret_cast<std::uintptr_t>(got.data()) % 16 == 0);
                std::vector<std::uint8_t> occluded(rays.size(), 7);
                std::vector<ImageTile> tiles;
                if (image.runs)  // a list's row as one tile, the last one short
                    for (std::uint32_t y = 0; y * run < rays.size(); ++y)
                        tiles.push_back(
                            {0, y, std::uint32_t(std::min<std::size_t>(rays.size() - y * run, run)), y + 1});
                else
                    for (std::uint32_t y0 = 0; y0 < camera.height(); y0 += 16)
                        for (std::uint32_t x0 = 0; x0 < camera.width(); x0 += 16)
                            tiles.push_back(
                                {x0, y0, std::min(x0 + 16, camera.width()), std::min(y0 + 16, camera.height())});
                for (const ImageTile& tile : tiles) {
                    CHECK(intersect_array_tile(accel, image, tile, got.data(), {width}));
                    CHECK(occlude_array_tile(accel, image, tile, occluded.data(), {width}));
                }
                _mm_sfence();
                std::size_t differ = 0;
                for (std::size_t i = 0; i < rays.size(); ++i)
                    differ += !same_bits(expected[i], got[i]) || expected_occluded[i] != occluded[i];
                CHECK(differ == 0);
            }
        }
        // A ray that cannot be traced fails its tile, whatever the width.
        std::vector<float> bad = six;  // in the bottom row of tiles, right of the first
        bad[6 * ((camera.height() - 2) * camera.width() + camera.width() - 3) + 4] =
            std::numeric_limits<float>::quiet_NaN();
        const StridedRays bad_arrays{
            .origins = bad.data(), .origin_stride = 6, .directions = bad.data() + 3, .direction_stride = 6};
        const RayImage bad_image{bad_arrays, camera.width()};
        std::vector<Hit> got(rays.size());
        for (SimdWidth width : {SimdWidth::scalar, SimdWidth::w4, SimdWidth::w8, SimdWidth::w16}) {
            if (!is_runnable(width)) continue;
            CHECK_FALSE(
                intersect_array_tile(accel, bad_image, {16, 16, camera.width(), camera.height()}, got.data(), {width}));
            CHECK(intersect_array_tile(accel, bad_image, {0, 16, 16, camera.height()}, got.data(), {width}));
        }
    }
}
