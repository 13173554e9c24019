// Ray packets through the BVH against the single-ray traversal, at every width this machine runs
// and with the single-ray switch off, at its default and taking every subtree: closest hits with
// the same t bits (and the same triangle, u and v unless two triangles tie at that t), the same
// any-hit answers, on camera pixel blocks of the built-in scenes, incoherent and mixed-sign
// packets, rays starting on box planes, windowed rays, partial packets and lanes switched off.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <span>
#include <stdexcept>
#include <vector>

#include "bvh_test_helpers.h"
#include "render/image_tiles.h"
#include "simd/each_arch.h"
#include "support/camera_rays.h"
#include "support/packet_agreement.h"
#include "support/random_scenes.h"
#include "support/sanitizer_workload.h"

using namespace trident;
using namespace trident::testing;

namespace {

/// Whether `got` is the single-ray triangle test's hit of `ray` on its triangle at exactly the t
/// of `expected`: another triangle of a tie.
template <TriangleTest Test>
bool is_tie(const Mesh& mesh, const Ray& ray, const Hit& got, const Hit& expected) {
    if (!got.is_hit() || !expected.is_hit() || !same_bits(got.t, expected.t)) return false;
    TriangleHit h;
    const bool hit = TriangleIntersector<Test>(ray).intersect(triangle_of(mesh, got.triangle), kInfinity, h);
    return hit && same_bits(h.t, got.t) && same_bits(h.u, got.u) && same_bits(h.v, got.v);
}

/// compare_packet_lanes() for the BVH's packets, with the single-ray switch at `single_ray_lanes`
/// (kDefaultSingleRayLanes: the width's own). Ties are allowed, but only between lanes of different
/// octants (bvh_packet.h).
template <class Arch, TriangleTest Test = TriangleTest::watertight, SlabTest Slabs = SlabTest::robust>
PacketComparison compare_packets(const Bvh& bvh, const Mesh& mesh, std::span<const Ray> rays, int single_ray_lanes,
                                 std::size_t rays_per_packet = 0, const LaneFilter& off = {}) {
    NoCounters none;
    const PacketVariant variant{.test = Test, .slabs = Slabs, .single_ray_lanes = single_ray_lanes};
    return compare_packet_lanes<Arch>(
        rays, rays_per_packet, off,
        [&](const RayPacket<Arch>& packet, HitPacket<Arch>& hits) {
            intersect_packet(bvh, packet, hits, none, variant);
            return simd::mask_bits(occlude_packet(bvh, packet, none, variant));
        },
        [&](const Ray& ray) { return bvh.intersect<Test, Slabs>(ray, none); },
        [&](const Ray& ray) { return bvh.occluded<Test, Slabs>(ray, none); },
        [&](const Ray& ray, const Hit& got, const Hit& expected) { return is_tie<Test>(mesh, ray, got, expected); });
}

/// Every packet width this machine runs, each with the single-ray switch off, at its default and
/// taking every subtree, on the same rays. Returns the ties met (lanes that kept another triangle).
template <TriangleTest Test = TriangleTest::watertight, SlabTest Slabs = SlabTest::robust>
std::size_t check_packets(const Bvh& bvh, const Mesh& mesh, std::span<const Ray> rays, const LaneFilter& off = {},
                          std::size_t rays_per_packet = 0) {
    std::size_t ties = 0;
    for_each_packet_arch([&]<class Arch>() {
        constexpr int width = int(RayPacket<Arch>::width);
        for (const PacketComparison& result :
             {compare_packets<Arch, Test, Slabs>(bvh, mesh, rays, 0, rays_per_packet, off),
              compare_packets<Arch, Test, Slabs>(bvh, mesh, rays, kDefaultSingleRayLanes, rays_per_packet, off),
              compare_packets<Arch, Test, Slabs>(bvh, mesh, rays, width, rays_per_packet, off)}) {
            CHECK(result.hits > 0);
            result.require_agreement();
            ties += result.ties;
        }
    });
    return ties;
}

}  // namespace

TEST_CASE("packets of incoherent rays find the single-ray hits at every width, for every builder setting") {
    BvhOptions sweep;
    sweep.builder = BvhBuilder::sweep_sah;
    BvhOptions one_per_leaf;
    one_per_leaf.max_leaf_size = 1;
    const Mesh mesh = random_soup(600, 11, 0.15f);
    const std::vector<Ray> rays = random_rays(mesh.bounds(), 400, 12);  // one in five axis-parallel
    for (const BvhOptions& options : {BvhOptions{}, BvhOptions::study(), sweep, one_per_leaf}) {
        CAPTURE(options.max_leaf_size);
        CAPTURE(to_string(options.builder));
        check_packets(Bvh::build(mesh, options), mesh, rays);
    }
    // The same rays grouped differently.
    std::vector<Ray> shuffled = rays;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(13));
    check_packets(Bvh::build(mesh), mesh, shuffled);
}

TEST_CASE("packets with the Möller-Trumbore test find its single-ray hits") {
    const Mesh mesh = random_soup(600, 21, 0.15f);
    check_packets<TriangleTest::moller_trumbore>(Bvh::build(mesh), mesh, random_rays(mesh.bounds(), 400, 22));
}

TEST_CASE("packets with the fast slab test find its single-ray hits, axis-parallel rays included") {
    const Mesh soup = random_soup(600, 23, 0.15f);
    check_packets<TriangleTest::watertight, SlabTest::fast>(Bvh::build(soup), soup,
                                                            random_rays(soup.bounds(), 400, 24));
    check_packets<TriangleTest::moller_trumbore, SlabTest::fast>(Bvh::build(soup), soup,
                                                                 rays_of_every_sign({0.05f, -0.1f, 0.2f}, 640, 25));
    const Mesh lattice = axis_lattice();
    check_packets<TriangleTest::watertight, SlabTest::fast>(Bvh::build(lattice), lattice, rays_on_lattice_planes());
}

TEST_CASE("mixed-sign packets, +0 and -0 included, find the single-ray hits") {
    const Mesh mesh = random_soup(600, 41, 0.12f);
    const Bvh bvh = Bvh::build(mesh);
    for (const Vec3f& origin : {Vec3f{0.05f, -0.1f, 0.2f}, Vec3f{-3.0f, 0.4f, 0.1f}}) {
        CAPTURE(origin.x);
        check_packets(bvh, mesh, rays_of_every_sign(origin, 640, 42));
    }
}

TEST_CASE("packets of axis-parallel rays starting on box planes, through shared edges, find the single-ray hits") {
    const Mesh mesh = axis_lattice();
    const std::vector<Ray> rays = rays_on_lattice_planes();
    std::vector<Ray> shuffled = rays;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(5));
    std::size_t shuffled_ties = 0;
    for (const int max_leaf : {1, 8}) {
        CAPTURE(max_leaf);
        BvhOptions options;
        options.max_leaf_size = max_leaf;
        const Bvh bvh = Bvh::build(mesh, options);
        check_packets(bvh, mesh, rays);
        shuffled_ties += check_packets(bvh, mesh, shuffled);
    }
    // Grouped at random, packets mix directions, and some lanes meet two edge-sharing triangles
    // at their t in the other order than alone: the tie allowance is exercised.
    CHECK(shuffled_ties > 0);
}

TEST_CASE("packets of rays from inside the scene with tmin/tmax windows find the single-ray hits") {
    const Mesh mesh = random_soup(600, 61, 0.15f);
    check_packets(Bvh::build(mesh), mesh, windowed_rays_from_inside(mesh.bounds(), 600, 62));
}

TEST_CASE("lanes switched off or with an empty window come back untouched and are never occluded") {
    const Mesh mesh = random_soup(500, 51, 0.15f);
    const Bvh bvh = Bvh::build(mesh);
    std::vector<Ray> rays = random_rays(mesh.bounds(), 400, 52);
    for (std::size_t i = 0; i < rays.size(); i += 7) {  // empty windows
        rays[i].tmin = 2.0f;
        rays[i].tmax = 1.0f;
    }
    SUBCASE("every third lane switched off") {
        check_packets(bvh, mesh, rays, [](std::size_t lane) { return lane % 3 == 1; });
    }
    SUBCASE("all lanes but one switched off") {
        check_packets(bvh, mesh, rays, [](std::size_t lane) { return lane != 2; });
    }
    SUBCASE("every lane switched off") {
        for_each_packet_arch([&]<class Arch>() {
            const PacketComparison result =
                compare_packets<Arch>(bvh, mesh, rays, 0, 0, [](std::size_t) { return true; });
            CHECK(result.lanes == 0);
            CHECK(result.untouched == 0);
            CHECK(result.padding == 0);
        });
    }
    SUBCASE("partial packets: fewer rays than lanes") {
        for_each_packet_arch([&]<class Arch>() {
            for (std::size_t count = 1; count < RayPacket<Arch>::width; count += 3) {
                CAPTURE(count);
                check_packets(bvh, mesh, rays, {}, count);
            }
        });
    }
}

TEST_CASE("an empty BVH leaves every lane a miss and occludes nothing") {
    const Mesh mesh;
    const Bvh bvh = Bvh::build(mesh);
    const std::vector<Ray> rays = random_rays({{-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f}}, 16, 81);
    for_each_packet_arch([&]<class Arch>() {
        const PacketComparison result = compare_packets<Arch>(bvh, mesh, rays, 0);
        CHECK(result.lanes == rays.size());
        CHECK(result.hits == 0);
        result.require_agreement();
    });
}

TEST_CASE(
    "camera pixel blocks of every built-in scene (2x2, 4x2, 4x4) and random camera rays find the single-ray hits") {
    for (const BuiltinSceneInfo& info : builtin_scenes_under_test()) {
        CAPTURE(info.name);
        const Scene& scene = builtin_scene(info.name);
        const Bvh& bvh = builtin_bvh(info.name);
        for_each_packet_arch([&]<class Arch>() {
            constexpr int width = int(RayPacket<Arch>::width);
            const auto [block_w, block_h] = packet_block(width);
            const std::vector<Ray> blocks =
                pixel_block_rays(scene.camera, 640, 360, int(block_w), int(block_h), 40, 91);
            const std::vector<Ray> random = camera_rays(scene.camera, 160, 92);
            for (const std::span<const Ray> rays : {std::span<const Ray>(blocks), std::span<const Ray>(random)}) {
                for (const PacketComparison& result :
                     {compare_packets<Arch>(bvh, scene.mesh, rays, 0),
                      compare_packets<Arch>(bvh, scene.mesh, rays, kDefaultSingleRayLanes)}) {
                    CHECK(result.hits > 0);
                    result.require_agreement();
                }
            }
        });
    }
}

TEST_CASE("the counters count per packet: at least the busiest lane's work, at most all lanes' together") {
    const Scene& scene = builtin_scene("teapot");
    const Bvh& bvh = builtin_bvh("teapot");
    for_each_packet_arch([&]<class Arch>() {
        constexpr std::size_t width = RayPacket<Arch>::width;
        const auto [block_w, block_h] = packet_block(width);
        const std::vector<Ray> rays = pixel_block_rays(scene.camera, 640, 360, int(block_w), int(block_h), 60, 101);
        PacketWorkTally tally;
        for (std::size_t first = 0; first < rays.size(); first += width) {
            const std::span<const Ray> chunk = std::span(rays).subspan(first, width);
            if (!lanes_share_octant(chunk, std::vector<bool>(width, true))) continue;  // others may visit more
            const RayPacket<Arch> packet(chunk);
            HitPacket<Arch> hits(packet);
            TraversalCounters one_packet;
            intersect_packet(bvh, packet, hits, one_packet, {.single_ray_lanes = 0});
            tally.add(one_packet, chunk, [&](const Ray& ray, TraversalCounters& one_ray) {
                bvh.intersect<TriangleTest::watertight>(ray, one_ray);
            });
        }
        CHECK(tally.counted > 40);
        tally.require_bounds();
        // Counted packet traversals are compiled for the robust slab test only: the fast one is refused.
        const RayPacket<Arch> packet(std::span<const Ray>(rays).first(width));
        HitPacket<Arch> hits(packet);
        TraversalCounters counters;
        CHECK_THROWS_AS(intersect_packet(bvh, packet, hits, counters, {.slabs = SlabTest::fast}),
                        std::invalid_argument);
    });
}

TEST_CASE("an any-hit packet stops each lane at its first hit: no more triangle tests than closest hit") {
    const Scene& scene = builtin_scene("hall");
    const Bvh& bvh = builtin_bvh("hall");
    for_each_packet_arch([&]<class Arch>() {
        constexpr std::size_t width = RayPacket<Arch>::width;
        const auto [block_w, block_h] = packet_block(width);
        const std::vector<Ray> rays = pixel_block_rays(scene.camera, 640, 360, int(block_w), int(block_h), 40, 111);
        TraversalCounters closest, any;
        for (std::size_t first = 0; first < rays.size(); first += width) {
            const RayPacket<Arch> packet(std::span<const Ray>(rays).subspan(first, width));
            HitPacket<Arch> hits(packet);
            intersect_packet(bvh, packet, hits, closest, {.single_ray_lanes = 0});
            occlude_packet(bvh, packet, any, {.single_ray_lanes = 0});
        }
        CHECK(any.triangles_tested < closest.triangles_tested);
        CHECK(any.nodes_visited < closest.nodes_visited);
    });
}
