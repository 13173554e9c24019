#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>

#include "core/ray_offset.h"
#include "render/ray_stream.h"
#include "render/render_kernels.h"
#include "render/render_plan.h"
#include "render/secondary_rays.h"
#include "render/shade.h"
#include "render/trace.h"
#include "render_test_scenes.h"
#include "scenes/builtin.h"
#include "support/packet_agreement.h"
#include "support/random_scenes.h"

using namespace trident;
using trident::testing::add_floor_quad;
using trident::testing::runnable_widths;

namespace {

/// A floor at y = 0, a square roof of side 2 at y = 1 over the origin, a wall at x = 8 facing
/// +-x, and the light at (0, 5, 0) above the roof.
Scene shadow_box() {
    Scene scene;
    scene.name = "shadow box";
    add_floor_quad(scene.mesh, -10, 10, -10, 10, 0);
    add_floor_quad(scene.mesh, -1, 1, -1, 1, 1);
    const auto a = scene.mesh.add_vertex({8, 0, -1}), b = scene.mesh.add_vertex({8, 3, -1});
    const auto c = scene.mesh.add_vertex({8, 3, 1}), d = scene.mesh.add_vertex({8, 0, 1});
    scene.mesh.add_triangle(a, b, c);
    scene.mesh.add_triangle(a, c, d);
    scene.light = PointLight{{0, 5, 0}};
    return scene;
}

/// Every structure and traversal: more than `min_hit_share` of the pixels see the scene, and
/// every pixel that does is lit (the scene has nothing between its surfaces and its light).
void check_every_hit_lit(const Scene& scene, const Camera& camera, double min_hit_share) {
    for (AccelKind kind : built_accel_kinds()) {
        const AnyAccel accel = AnyAccel::build(kind, scene.mesh);
        for (SimdWidth width : runnable_widths()) {
            if (!has_packet_traversal(accel, width)) continue;
            CAPTURE(std::string(to_string(kind)));
            CAPTURE(std::string(to_string(width)));
            RenderRequest request;
            request.width = width;
            const RenderPlan plan = make_render_plan(scene, request);
            REQUIRE(plan.shadow_pass);
            const std::vector<Hit> hits = trace_primary(accel, camera, TriangleTest::watertight, width);
            const std::vector<std::uint8_t> lit = light_visibility(scene, accel, camera, hits, plan);
            std::size_t hit_pixels = 0, dark = 0;
            for (std::size_t i = 0; i < hits.size(); ++i)
                if (hits[i].is_hit()) {
                    ++hit_pixels;
                    dark += !lit[i];
                }
            CHECK(double(hit_pixels) > min_hit_share * double(hits.size()));
            CHECK(dark == 0);
        }
    }
}

}  // namespace

TEST_CASE("shadow rays: full light, a known shadow, and a surface facing away, for every structure and width") {
    const Scene scene = shadow_box();
    const Vec3f light = scene.light->position;
    // Primary rays: onto the open floor; onto the floor under the roof (from below the roof);
    // onto the wall's far side (the light is behind it).
    const Ray open_floor{{5, 10, 5}, {0, -1, 0}};
    const Ray under_roof{{0.3f, 0.5f, 0.2f}, {0, -1, 0}};
    const Ray wall_back{{9, 1, 0}, {-1, 0, 0}};
    for (AccelKind kind : built_accel_kinds()) {
        const AnyAccel accel = AnyAccel::build(kind, scene.mesh);
        std::vector<Ray> shadow;
        for (const Ray& primary : {open_floor, under_roof, wall_back}) {
            NoCounters counters;
            const Hit hit = accel.visit([&](const auto& s) { return s.template intersect<TriangleTest::watertight>(primary, counters); });
            REQUIRE(hit.is_hit());
            shadow.push_back(shadow_ray(scene.mesh, primary, hit, light));
        }
        CHECK(shadow[0].tmax > shadow[0].tmin);
        CHECK(shadow[1].tmax > shadow[1].tmin);
        CHECK_FALSE(shadow[2].tmax > shadow[2].tmin);  // facing away: no ray, in shadow
        for (SimdWidth width : runnable_widths()) {
            if (!has_packet_traversal(accel, width)) continue;
            CAPTURE(to_string(kind));
            CAPTURE(to_string(width));
            std::vector<std::uint8_t> occluded(shadow.size(), 7);
            occlude_stream(accel, shadow, occluded, {width, PacketGrouping::in_order});
            CHECK(occluded[0] == 0);
            CHECK(occluded[1] == 1);
            CHECK(occluded[2] == 0);  // not traced
        }
    }
}

TEST_CASE("shadow rays: a flat lit plane far from the origin has no self-shadowed pixel (no acne)") {
    Scene scene;
    scene.name = "plane";
    // A 24x24 grid of quads around (1000, 37, -2000): large coordinates, many shared edges.
    const Vec3f c{1000.0f, 37.0f, -2000.0f};
    for (int i = 0; i < 24; ++i)
        for (int j = 0; j < 24; ++j)
            add_floor_quad(scene.mesh, c.x - 12 + float(i), c.x - 11 + float(i), c.z - 12 + float(j), c.z - 11 + float(j), c.y);
    scene.light = PointLight{c + Vec3f{30.0f, 4.0f, 20.0f}};  // low: shadow rays graze the plane
    scene.camera = CameraSpec{c + Vec3f{0.0f, 6.0f, 14.0f}, c, {0, 1, 0}, 60.0f};
    check_every_hit_lit(scene, Camera(scene.camera, 48, 32), 0.5);
}

TEST_CASE("shadow rays: a large floor seen from afar has no self-shadowed pixel (no acne)") {
    // Room's floor (../shared/scenes), reduced: y near zero where the other two coordinates are in
    // the thousands, quads 1,600 units wide, primary rays about 2,500 units long. Two ways to fail,
    // each seen on Room (bench/experiments/shadow-diffuse.md): a hit point computed as origin + t * dir is off the
    // plane by up to t * 2^-24, more than the offset of 256 ulps of its y, and can start the
    // shadow ray below the floor; and from a point that close to a plane, the triangle test's
    // rounding in t reaches across it, so the coplanar neighbours come out hit at t near 0 by any
    // structure that tests them there (brute force and the octree, whose cells hold the origin).
    Scene scene;
    scene.name = "floor";
    for (int i = -1; i < 1; ++i)
        for (int j = -1; j < 1; ++j)
            add_floor_quad(scene.mesh, 1600.0f * float(i), 1600.0f * float(i + 1), 1600.0f * float(j),
                           1600.0f * float(j + 1), -1.5721590f);
    scene.light = PointLight{{100.0f, 900.0f, -200.0f}};
    scene.camera = CameraSpec{{-700.0f, 420.0f, 2300.0f}, {300.0f, 0.0f, -900.0f}, {0, 1, 0}, 60.0f};
    const Camera camera(scene.camera, 96, 64);
    const float floor_y = scene.mesh.bounds().lo.y;
    {
        // The premise: origin + t * dir strays from the floor by more than the offset, while the
        // point from the barycentrics stays on it.
        const std::vector<Hit> hits = trace_primary(AnyAccel::build(AccelKind::bvh, scene.mesh), camera);
        float worst_stray = 0.0f, worst_surface = 0.0f;
        for (std::size_t i = 0; i < hits.size(); ++i) {
            if (!hits[i].is_hit()) continue;
            const Ray primary = camera.primary_ray(std::uint32_t(i % 96), std::uint32_t(i / 96));
            worst_stray = std::max(worst_stray, std::abs((primary.origin + primary.dir * hits[i].t).y - floor_y));
            worst_surface = std::max(worst_surface, std::abs(surface_point(scene.mesh, hits[i]).y - floor_y));
        }
        const float offset = offset_ray_origin({0.0f, floor_y, 0.0f}, {0.0f, 1.0f, 0.0f}).y - floor_y;
        CHECK(worst_stray > 2.0f * offset);
        CHECK(worst_surface == 0.0f);
    }
    check_every_hit_lit(scene, camera, 0.33);
}

TEST_CASE("occlusion agrees with closest hit on incoherent rays, for every structure, width and grouping") {
    const Scene scene = make_builtin_scene("teapot");
    const Camera camera(scene.camera, 40, 24);
    const AnyAccel bvh = AnyAccel::build(AccelKind::bvh, scene.mesh);
    const std::vector<Hit> primary = trace_primary(bvh, camera);
    SecondaryRays diffuse = make_diffuse_rays(scene.mesh, camera, primary, 1, 11);
    REQUIRE(diffuse.rays.size() > 100);
    // Finite ends, so some rays stop short of what they would hit.
    std::mt19937 rng(5);
    const float diagonal = length(scene.mesh.bounds().extent());
    std::uniform_real_distribution<float> end(0.0f, 0.5f * diagonal);
    for (std::size_t i = 0; i < diffuse.rays.size(); ++i)
        if (i % 3 != 0) diffuse.rays[i].tmax = end(rng);
    for (AccelKind kind : built_accel_kinds()) {
        const AnyAccel accel = AnyAccel::build(kind, scene.mesh);
        std::vector<Hit> scalar_hits(diffuse.rays.size());
        intersect_stream(accel, diffuse.rays, scalar_hits, {});
        // The incoherent hint may change how a structure walks (the wide BVH prefetches), not what it finds.
        std::vector<Hit> hinted(diffuse.rays.size());
        intersect_stream(accel, diffuse.rays, hinted, {.coherence = RayCoherence::incoherent});
        std::size_t hinted_differs = 0;
        for (std::size_t i = 0; i < hinted.size(); ++i) hinted_differs += !testing::same_bits(hinted[i], scalar_hits[i]);
        CHECK(hinted_differs == 0);
        std::size_t occluded_count = 0;
        for (SimdWidth width : runnable_widths()) {
            if (!has_packet_traversal(accel, width)) continue;
            for (PacketGrouping grouping : {PacketGrouping::in_order, PacketGrouping::by_octant}) {
                CAPTURE(to_string(kind));
                CAPTURE(to_string(width));
                CAPTURE(to_string(grouping));
                std::vector<std::uint8_t> occluded(diffuse.rays.size());
                std::vector<Hit> hits(diffuse.rays.size());
                occlude_stream_parallel(accel, diffuse.rays, occluded, {width, grouping});
                intersect_stream_parallel(accel, diffuse.rays, hits, {width, grouping});
                std::size_t disagree = 0, differ_from_scalar = 0;
                occluded_count = 0;
                for (std::size_t i = 0; i < hits.size(); ++i) {
                    disagree += bool(occluded[i]) != hits[i].is_hit();
                    differ_from_scalar += hits[i].triangle != scalar_hits[i].triangle || hits[i].t != scalar_hits[i].t;
                    occluded_count += occluded[i];
                }
                CHECK(disagree == 0);
                CHECK(differ_from_scalar == 0);
            }
        }
        CHECK(occluded_count > 0);                    // the test sees both answers
        CHECK(occluded_count < diffuse.rays.size());
    }
}

TEST_CASE("incoherent packets over a large wide BVH go from the stream as single rays, with the single rays' hits") {
    // A tree of at least kIncoherentAloneMinBlocks blocks, and rays in every direction from random
    // points inside it, some stopping short.
    const Mesh soup = testing::random_soup(5 * kIncoherentAloneMinBlocks, 61, 0.02f);
    std::vector<Ray> rays = testing::random_rays(soup.bounds(), 3000, 62);
    std::mt19937 rng(63);
    std::uniform_real_distribution<float> end(0.0f, 1.0f);
    // Rays 1000-1399 nearly parallel: their packets walk the tree as packets between the packets
    // that go alone; every 7th ray not traced (tmax < tmin), inside the runs of single rays too.
    std::uniform_real_distribution<float> tilt(0.0f, 0.05f);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        rays[i].origin = rays[i].origin * 0.3f;  // inside the soup, so rays start among triangles
        if (i % 4 == 0) rays[i].tmax = end(rng);
        if (i >= 1000 && i < 1400) rays[i].dir = {1.0f, 0.1f + tilt(rng), tilt(rng)};
        if (i % 7 == 3) rays[i].tmax = -1.0f;
    }
    const AnyAccel accel = AnyAccel::build(AccelKind::bvh, soup);
    accel.visit([&](const auto& structure) {
        const auto eight_from = [](std::size_t first) {
            std::vector<std::size_t> index(8);
            std::iota(index.begin(), index.end(), first);
            return index;
        };
        if constexpr (WalksLanesAlone<std::decay_t<decltype(structure)>>) {
            REQUIRE(structure.blocks().size() >= kIncoherentAloneMinBlocks);
            CHECK(structure.packet_walks_lanes_alone(rays, eight_from(0)));
            CHECK_FALSE(structure.packet_walks_lanes_alone(rays, eight_from(1000)));  // within the cone
        } else {
            FAIL("bvh is not the wide BVH");
        }
    });
    std::vector<Hit> scalar_hits(rays.size());
    std::vector<std::uint8_t> scalar_occluded(rays.size());
    intersect_stream(accel, rays, scalar_hits, {});
    occlude_stream(accel, rays, scalar_occluded, {});
    std::size_t hit_count = 0;
    for (const Hit& hit : scalar_hits) hit_count += hit.is_hit();
    CHECK(hit_count > rays.size() / 4);  // the test sees both answers
    CHECK(hit_count < rays.size());
    // A small tree's incoherent packets walk as packets, where their lanes share most nodes.
    const AnyAccel small =
        AnyAccel::build(AccelKind::bvh, testing::random_soup(kIncoherentAloneMinBlocks / 4, 64, 0.1f));
    for (SimdWidth width : runnable_widths()) {
        for (PacketGrouping grouping : {PacketGrouping::in_order, PacketGrouping::by_octant}) {
            // The caller's incoherent hint sends the large tree's stream ray by ray from the start,
            // without cutting packets.
            for (RayCoherence coherence : {RayCoherence::coherent, RayCoherence::incoherent}) {
                CAPTURE(std::string(to_string(width)));
                CAPTURE(std::string(to_string(grouping)));
                CAPTURE(coherence == RayCoherence::incoherent);
                const StreamTraversal traversal{width, grouping, SlabTest::robust, coherence};
                const bool packets = width != SimdWidth::scalar;  // single rays are not asked
                CHECK(stream_walks_rays_alone(accel, traversal) == (packets && coherence == RayCoherence::incoherent));
                CHECK_FALSE(stream_walks_rays_alone(small, traversal));
                std::vector<Hit> hits(rays.size());
                std::vector<std::uint8_t> occluded(rays.size());
                intersect_stream(accel, rays, hits, traversal);
                occlude_stream(accel, rays, occluded, traversal);
                std::size_t hits_differ = 0, occlusion_differs = 0;
                for (std::size_t i = 0; i < rays.size(); ++i) {
                    hits_differ += !testing::same_bits(hits[i], scalar_hits[i]);
                    occlusion_differs += occluded[i] != scalar_occluded[i];
                }
                CHECK(hits_differ == 0);
                CHECK(occlusion_differs == 0);
            }
        }
    }
    CHECK_FALSE(stream_walks_rays_alone(
        accel, {SimdWidth::scalar, PacketGrouping::in_order, SlabTest::robust, RayCoherence::incoherent}));
}
