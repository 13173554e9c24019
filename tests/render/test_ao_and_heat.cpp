#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "render/heat_map.h"
#include "render/hemisphere_sample.h"
#include "render/render_plan.h"
#include "render/shade.h"
#include "render/trace.h"
#include "render_test_scenes.h"
#include "scenes/builtin.h"

using namespace trident;
using trident::testing::add_floor_quad;
using trident::testing::runnable_widths;

TEST_CASE("cosine directions: unit, above the surface, mean cosine 2/3, no tangential bias") {
    const Vec3f n = normalize(Vec3f{0.3f, -0.8f, 0.5f});
    const Frame f = frame_around(n);
    CHECK(std::abs(dot(f.tangent, n)) < 1e-5f);
    CHECK(std::abs(dot(f.bitangent, n)) < 1e-5f);
    CHECK(std::abs(dot(f.tangent, f.bitangent)) < 1e-5f);
    double mean_cos = 0.0, mean_t = 0.0;
    constexpr int kSamples = 40000;
    for (int i = 0; i < kSamples; ++i) {
        const Vec3f d = cosine_direction(n, sample_uniforms(std::uint64_t(i) / 4, std::uint32_t(i % 4), 3));
        CHECK(std::abs(length(d) - 1.0f) < 1e-5f);
        CHECK(dot(d, n) >= 0.0f);
        mean_cos += dot(d, n);
        mean_t += dot(d, f.tangent);
    }
    // For density cos/pi, E[cos] = 2/3; the standard error at 40k samples is about 0.0012.
    CHECK(mean_cos / kSamples == doctest::Approx(2.0 / 3.0).epsilon(0.01));
    CHECK(std::abs(mean_t / kSamples) < 0.01);
}

TEST_CASE("sample numbers are a pure function of pixel, sample and seed") {
    const UniformPair a = sample_uniforms(1234, 5, 9), b = sample_uniforms(1234, 5, 9);
    CHECK(a.u1 == b.u1);
    CHECK(a.u2 == b.u2);
    const UniformPair c = sample_uniforms(1234, 6, 9), d = sample_uniforms(1235, 5, 9), e = sample_uniforms(1234, 5, 10);
    CHECK((c.u1 != a.u1 || c.u2 != a.u2));
    CHECK((d.u1 != a.u1 || d.u2 != a.u2));
    CHECK((e.u1 != a.u1 || e.u2 != a.u2));
    CHECK((a.u1 >= 0.0f && a.u1 < 1.0f && a.u2 >= 0.0f && a.u2 < 1.0f));
}

TEST_CASE("ambient occlusion is identical with 1 and 2 threads and with every traversal") {
    const Scene scene = make_builtin_scene("teapot");
    const Camera camera(scene.camera, 45, 27);  // partial tiles and partial packet blocks
    RenderRequest request;
    request.mode = RenderMode::ao;
    request.ao_samples = 6;
    for (AccelKind kind : {AccelKind::bvh, AccelKind::kdtree, AccelKind::octree}) {
        const AnyAccel accel = AnyAccel::build(kind, scene.mesh);
        const std::vector<Hit> hits = trace_primary(accel, camera);
        std::vector<float> first;
        for (SimdWidth width : runnable_widths()) {
            if (!has_packet_traversal(accel, width)) continue;
            request.width = width;
            const RenderPlan plan = make_render_plan(scene, request);
            for (std::size_t threads : {1u, 2u}) {
                CAPTURE(to_string(kind));
                CAPTURE(to_string(width));
                CAPTURE(threads);
                const tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, threads);
                const std::vector<float> open = ambient_visibility(scene, accel, camera, hits, plan);
                if (first.empty()) {
                    first = open;
                    std::size_t partly = 0;
                    for (float v : open) partly += v < 1.0f;
                    CHECK(partly > 0);  // the teapot occludes itself somewhere
                } else {
                    CHECK(open == first);
                }
            }
        }
    }
}

TEST_CASE("an open plane has no ambient occlusion") {
    Scene scene;
    add_floor_quad(scene.mesh, -5, 5, -5, 5, 0);
    scene.camera = CameraSpec{{0, 3, 4}, {0, 0, 0}, {0, 1, 0}, 50.0f};
    const Camera camera(scene.camera, 24, 16);
    RenderRequest request;
    request.mode = RenderMode::ao;
    const AnyAccel accel = AnyAccel::build(AccelKind::bvh, scene.mesh);
    const std::vector<Hit> hits = trace_primary(accel, camera);
    const std::vector<float> open = ambient_visibility(scene, accel, camera, hits, make_render_plan(scene, request));
    for (float v : open) CHECK(v == 1.0f);
}

TEST_CASE("heat map legend spells the image's minimum and maximum") {
    const Camera camera(CameraSpec{}, 200, 120);
    std::vector<TraversalCounters> counts(std::size_t(200) * 120);
    for (std::size_t i = 0; i < counts.size(); ++i) counts[i].nodes_visited = 3 + i % 905;  // 3..907
    const Image image = shade_heat(camera, counts, HeatMeasure::nodes);
    const HeatLegendLayout layout = heat_legend_layout(200, 120, 907);
    const Rgb8 white{255, 255, 255};
    CHECK(read_digit(image, layout.min_x, layout.digits_y, layout.scale, white) == 3);
    CHECK(read_digit(image, layout.max_x, layout.digits_y, layout.scale, white) == 9);
    CHECK(read_digit(image, layout.max_x + 4 * layout.scale, layout.digits_y, layout.scale, white) == 0);
    CHECK(read_digit(image, layout.max_x + 8 * layout.scale, layout.digits_y, layout.scale, white) == 7);
    // Above the legend the ramp runs from dark (minimum) to white-hot (maximum).
    CHECK(image.at(0, 0).r < 40);
    const Image tiny = shade_heat(Camera(CameraSpec{}, 20, 10), std::vector<TraversalCounters>(200), HeatMeasure::nodes);
    CHECK(tiny.width == 20);  // too small for a legend: none drawn, no crash
}

TEST_CASE("packet heat counts: one count per packet block, and at least the scalar count of some lane") {
    const Scene scene = make_builtin_scene("teapot");
    const Camera camera(scene.camera, 32, 16);
    for (AccelKind kind : {AccelKind::bvh, AccelKind::kdtree, AccelKind::octree}) {
        const AnyAccel accel = AnyAccel::build(kind, scene.mesh);
        const std::vector<TraversalCounters> scalar = count_primary_rays(accel, camera, SimdWidth::scalar);
        for (SimdWidth width : runnable_widths()) {
            if (width == SimdWidth::scalar || !has_packet_traversal(accel, width)) continue;
            CAPTURE(to_string(kind));
            CAPTURE(to_string(width));
            const std::vector<TraversalCounters> packed = count_primary_rays(accel, camera, width);
            const auto [bw, bh] = packet_block(lane_count(width));
            std::size_t uneven = 0, below = 0, total = 0;
            for (std::uint32_t by = 0; by < camera.height(); by += bh)
                for (std::uint32_t bx = 0; bx < camera.width(); bx += bw) {
                    const TraversalCounters& block = packed[std::size_t(by) * camera.width() + bx];
                    std::uint64_t most = 0;
                    for (std::uint32_t y = by; y < by + bh; ++y)
                        for (std::uint32_t x = bx; x < bx + bw; ++x) {
                            const std::size_t i = std::size_t(y) * camera.width() + x;
                            uneven += packed[i].nodes_visited != block.nodes_visited;
                            most = std::max(most, scalar[i].nodes_visited);
                        }
                    below += block.nodes_visited == 0 && most > 0;
                    total += block.nodes_visited;
                }
            CHECK(uneven == 0);
            CHECK(below == 0);
            CHECK(total > 0);
        }
    }
}
