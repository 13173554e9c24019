#include <doctest/doctest.h>

#include <algorithm>
#include <string>

#include "render/render_plan.h"
#include "scenes/builtin.h"

using namespace trident;

namespace {

Scene one_triangle(bool light, bool normals) {
    Scene scene;
    scene.name = "tri";
    scene.mesh.add_vertex({0, 0, 0});
    scene.mesh.add_vertex({1, 0, 0});
    scene.mesh.add_vertex({0, 1, 0});
    scene.mesh.add_triangle(0, 1, 2);
    if (normals) {
        scene.mesh.nx = {0.0f};
        scene.mesh.ny = {0.0f};
        scene.mesh.nz = {1.0f};
        scene.mesh.normal_triangles = {{0, 0, 0}};
    }
    if (light) scene.light = PointLight{{0.2f, 0.2f, 5.0f}};
    return scene;
}

bool says(const RenderPlan& plan, const std::string& start, const std::string& word) {
    return std::any_of(plan.explanation.begin(), plan.explanation.end(), [&](const std::string& line) {
        return line.starts_with(start) && line.find(word) != std::string::npos;
    });
}

}  // namespace

TEST_CASE("plan: a lit scene with normals shades with shadow rays and interpolated normals") {
    const RenderPlan plan = make_render_plan(one_triangle(true, true), {});
    CHECK(plan.shadow_pass);
    CHECK(plan.light_source == LightSource::scene);
    CHECK(plan.normals == NormalSource::interpolated);
    CHECK(plan.reads_barycentrics);
    CHECK(plan.shades);
    CHECK_FALSE(plan.occlusion_pass);
    CHECK_FALSE(plan.counts_traversal);
    CHECK(says(plan, "shadow:", "any-hit"));
}

TEST_CASE("plan: no light means no shadow pass; no normals means the geometric normal") {
    const RenderPlan plan = make_render_plan(one_triangle(false, false), {});
    CHECK_FALSE(plan.shadow_pass);
    CHECK_FALSE(plan.light);
    CHECK(plan.normals == NormalSource::geometric);
    CHECK_FALSE(plan.reads_barycentrics);
    CHECK(says(plan, "shadow:", "no light"));
    CHECK(says(plan, "normals:", "geometric"));
}

TEST_CASE("plan: modes that show no lighting trace no shadow rays even with a light") {
    for (RenderMode mode : {RenderMode::depth, RenderMode::normal, RenderMode::heat, RenderMode::ao}) {
        RenderRequest request;
        request.mode = mode;
        const RenderPlan plan = make_render_plan(one_triangle(true, true), request);
        CAPTURE(to_string(mode));
        CHECK_FALSE(plan.shadow_pass);
        CHECK(plan.occlusion_pass == (mode == RenderMode::ao));
        CHECK(plan.counts_traversal == (mode == RenderMode::heat));
        CHECK(plan.normals == (mode == RenderMode::depth || mode == RenderMode::heat ? NormalSource::none
                                                                                       : NormalSource::interpolated));
    }
}

TEST_CASE("plan: benchmark timing is visibility only, and shadow rays without a light use the default light") {
    RenderRequest request;
    request.benchmark = BenchmarkRays{true, true};
    const Scene dark = one_triangle(false, true);
    const RenderPlan plan = make_render_plan(dark, request);
    CHECK_FALSE(plan.shades);
    CHECK(plan.normals == NormalSource::none);
    CHECK_FALSE(plan.reads_barycentrics);
    REQUIRE(plan.shadow_pass);
    CHECK(plan.light_source == LightSource::default_from_box);
    CHECK(plan.light->position.y > dark.mesh.bounds().hi.y);  // above the box
    CHECK(says(plan, "shadow:", "default light"));
    CHECK(plan.occlusion_pass);
    CHECK(plan.occlusion_samples == 1);
    CHECK(says(plan, "shade:", "skipped"));

    const RenderPlan lit = make_render_plan(one_triangle(true, false), request);
    CHECK(lit.light_source == LightSource::scene);

    request.benchmark = BenchmarkRays{};
    const RenderPlan primary_only = make_render_plan(dark, request);
    CHECK_FALSE(primary_only.shadow_pass);
    CHECK_FALSE(primary_only.occlusion_pass);
}

TEST_CASE("plan: ao samples and heat measure pass through; modes and measures parse") {
    RenderRequest request;
    request.mode = RenderMode::ao;
    request.ao_samples = 7;
    CHECK(make_render_plan(one_triangle(false, false), request).occlusion_samples == 7);
    CHECK(make_render_plan(one_triangle(false, false), request).occlusion_radius > 0.0f);
    request.mode = RenderMode::heat;
    request.heat = HeatMeasure::triangles;
    CHECK(make_render_plan(one_triangle(false, false), request).heat == HeatMeasure::triangles);
    CHECK(parse_render_mode("ao") == RenderMode::ao);
    CHECK_FALSE(parse_render_mode("fancy"));
    CHECK(parse_heat_measure("triangles") == HeatMeasure::triangles);
    CHECK_FALSE(parse_heat_measure("leaves"));
}

TEST_CASE("plan: incoherent rays take the traversal measured best per structure, width and size") {
    const auto is_single = [](const StreamTraversal& t) { return t.width == SimdWidth::scalar; };
    for (AccelKind accel : {AccelKind::bvh, AccelKind::kdtree, AccelKind::octree}) {
        CHECK(is_single(incoherent_traversal(accel, SimdWidth::scalar, 1000)));
        CHECK(incoherent_traversal(accel, SimdWidth::scalar, 1000).coherence == RayCoherence::incoherent);
    }
    const bool has16 = is_runnable(SimdWidth::w16);
    for (SimdWidth asked : {SimdWidth::w4, SimdWidth::w8, SimdWidth::w16}) {
        if (!is_runnable(asked)) continue;
        CAPTURE(int(asked));
        for (std::size_t triangles : {std::size_t(50000), std::size_t(1000000)}) {
            const StreamTraversal bvh = incoherent_traversal(AccelKind::bvh, asked, triangles);
            const StreamTraversal kd = incoherent_traversal(AccelKind::kdtree, asked, triangles);
            const StreamTraversal octree = incoherent_traversal(AccelKind::octree, asked, triangles);
            CHECK(bvh.width == (has16 ? SimdWidth::w16 : is_runnable(SimdWidth::w8) ? SimdWidth::w8 : asked));
            CHECK(kd.width == (has16 ? SimdWidth::w16 : SimdWidth::w4));
            // Narrow octree packets lose above 100k triangles: single rays there, unless 16 lanes run.
            CHECK(octree.width == (has16 ? SimdWidth::w16 : triangles < 100000 ? asked : SimdWidth::scalar));
            for (const StreamTraversal& t : {bvh, kd, octree}) {
                if (!is_single(t)) CHECK(t.grouping == PacketGrouping::by_octant);
                CHECK(t.coherence == RayCoherence::incoherent);
            }
        }
    }
}
