// Ray packets through the octree against the single-ray traversal, at every width this machine
// runs: every lane must give the single-ray hit bit for bit (triangle, t, u, v) and the same
// any-hit answer, on coherent camera packets, incoherent and mixed-sign packets, rays along the
// octree's planes, windowed rays, partial packets and packets with lanes switched off.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "accel/octree/octree.h"
#include "accel/octree/octree_packet.h"
#include "octree/octree_meshes.h"
#include "octree/octree_test_support.h"
#include "simd/each_arch.h"
#include "simd/hit_lanes.h"
#include "support/camera_rays.h"
#include "support/packet_agreement.h"
#include "support/random_scenes.h"
#include "support/sanitizer_workload.h"

#if __has_include("scenes/builtin.h")
#include "scenes/builtin.h"
#define TRIDENT_TEST_BUILTIN_SCENES 1
#endif

using namespace trident;
using namespace trident::testing;

namespace {

/// compare_packet_lanes() for the octree's packets, with the single-ray switch at
/// `single_ray_lanes` (kDefaultSingleRayLanes: kOctreeSingleRayLanes); no ties allowed
/// (octree_packet.h).
template <class Arch, TriangleTest Test = TriangleTest::watertight, SlabTest Slabs = SlabTest::robust>
PacketComparison compare_packets(const Octree& tree, std::span<const Ray> rays, std::size_t rays_per_packet = 0,
                                 const LaneFilter& off = {}, int single_ray_lanes = kDefaultSingleRayLanes) {
    NoCounters none;
    const PacketVariant variant{.test = Test, .slabs = Slabs, .single_ray_lanes = single_ray_lanes};
    return compare_packet_lanes<Arch>(
        rays, rays_per_packet, off,
        [&](const RayPacket<Arch>& packet, HitPacket<Arch>& hits) {
            intersect_packet(tree, packet, hits, none, variant);
            return simd::mask_bits(occlude_packet(tree, packet, none, variant));
        },
        [&](const Ray& ray) { return tree.intersect<Test, Slabs>(ray, none); },
        [&](const Ray& ray) { return tree.occluded<Test, Slabs>(ray, none); });
}

/// Every packet width this machine runs, each on the same rays.
template <TriangleTest Test = TriangleTest::watertight, SlabTest Slabs = SlabTest::robust>
void check_packets(const Octree& tree, std::span<const Ray> rays, const LaneFilter& off = {}) {
    for_each_packet_arch([&]<class Arch>() {
        const PacketComparison result = compare_packets<Arch, Test, Slabs>(tree, rays, 0, off);
        CHECK(result.hits > 0);
        result.require_agreement();
    });
}

}  // namespace

TEST_CASE("packets of incoherent rays give the single-ray hits bit for bit, at every width and depth") {
    const Mesh mesh = random_soup(500, 11, 0.15f);
    const std::vector<Ray> rays = random_rays(mesh.bounds(), 500, 12);  // one in five axis-parallel
    for (const int depth : {0, 1, 4, 8}) {
        for (const OctreeOverlap overlap : {OctreeOverlap::triangle, OctreeOverlap::bounding_box}) {
            CAPTURE(depth);
            CAPTURE(int(overlap));
            check_packets(Octree::build(mesh, {.max_depth = depth, .overlap = overlap}), rays);
        }
    }
    // The same rays grouped differently.
    std::vector<Ray> shuffled = rays;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(13));
    check_packets(Octree::build(mesh, {}), shuffled);
}

TEST_CASE("packets with the Möller-Trumbore test give its single-ray hits bit for bit") {
    const Mesh mesh = random_soup(500, 21, 0.15f);
    check_packets<TriangleTest::moller_trumbore>(Octree::build(mesh, {}), random_rays(mesh.bounds(), 400, 22));
}

TEST_CASE("packets with the fast slab test (no widened cell exit) give its single-ray hits bit for bit") {
    const Mesh mesh = random_soup(500, 23, 0.15f);
    check_packets<TriangleTest::watertight, SlabTest::fast>(Octree::build(mesh, {}),
                                                            random_rays(mesh.bounds(), 400, 24));
    const Mesh grid = flat_grid(16);
    const Octree tree = Octree::build(grid, {.max_depth = 6});
    check_packets<TriangleTest::moller_trumbore, SlabTest::fast>(tree, rays_along_the_planes(tree, 8, 3));
}

TEST_CASE("packets of rays through node centres, in centre planes and along cell edges match single rays") {
    const Mesh mesh = random_soup(600, 31, 0.1f);
    for (const int depth : {3, 6}) {
        CAPTURE(depth);
        const Octree tree = Octree::build(mesh, {.max_depth = depth});
        check_packets(tree, rays_along_the_planes(tree, 5, 3));
    }
    // Axis-aligned geometry on the planes themselves: hits on cell faces end lanes there.
    const Mesh grid = flat_grid(16);
    const Octree tree = Octree::build(grid, {.max_depth = 6});
    check_packets(tree, rays_along_the_planes(tree, 8, 3));
}

TEST_CASE("subtrees walked lane by lane, for any number of lanes, give the packet walk's hits") {
    const Mesh mesh = random_soup(500, 33, 0.15f);
    const Octree tree = Octree::build(mesh, {});
    std::vector<Ray> rays = random_rays(mesh.bounds(), 300, 34);
    const std::vector<Ray> planes = rays_along_the_planes(tree, 34, 1);
    rays.insert(rays.end(), planes.begin(), planes.end());
    const CameraSpec camera{{0.3f, -0.2f, 3.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 60.0f};
    const std::vector<Ray> blocks = pixel_block_rays(camera, 64, 36, 4, 4, 20, 35);
    for_each_packet_arch([&]<class Arch>() {
        const int width = int(RayPacket<Arch>::width);
        for (const int single_ray_lanes : {0, 1, 2, width / 2, width}) {
            CAPTURE(single_ray_lanes);
            compare_packets<Arch>(tree, rays, 0, {}, single_ray_lanes).require_agreement();
            compare_packets<Arch>(
                tree, blocks, 0, [](std::size_t lane) { return lane % 5 == 3; }, single_ray_lanes)
                .require_agreement();
        }
    });
}

TEST_CASE("a packet of one ray in every lane does exactly the single ray's work, ties at cell edges included") {
    // Equal counts mean the lanes walk the same cells: on rays through node centres and along cell
    // edges, a different tie rule would enter other (empty or missing) children.
    const Mesh mesh = random_soup(600, 35, 0.1f);
    const Octree tree = Octree::build(mesh, {.max_depth = 6});
    std::vector<Ray> rays = rays_along_the_planes(tree, 36, 3);
    const std::vector<Ray> random = random_rays(mesh.bounds(), 200, 37);
    rays.insert(rays.end(), random.begin(), random.end());
    for_each_packet_arch([&]<class Arch>() {
        static_assert(kOctreeSingleRayLanes<Arch> < int(RayPacket<Arch>::width), "the packet walk must run");
        std::size_t different_work = 0, different_hits = 0;
        for (const Ray& ray : rays) {
            const std::vector<Ray> copies(RayPacket<Arch>::width, ray);
            const RayPacket<Arch> packet(copies);
            HitPacket<Arch> hits(packet);
            TraversalCounters single, packed, single_any, packed_any;
            const Hit expected = tree.intersect<TriangleTest::watertight>(ray, single);
            intersect_packet(tree, packet, hits, packed);
            tree.occluded<TriangleTest::watertight>(ray, single_any);
            occlude_packet(tree, packet, packed_any);
            different_work += single.nodes_visited != packed.nodes_visited ||
                              single.triangles_tested != packed.triangles_tested ||
                              single_any.nodes_visited != packed_any.nodes_visited ||
                              single_any.triangles_tested != packed_any.triangles_tested;
            std::array<Hit, RayPacket<Arch>::width> got;
            const simd::HitLanes<Arch> lanes(hits);
            for (std::size_t i = 0; i < got.size(); ++i) lanes.store_lane(i, &got[i]);
            different_hits +=
                std::count_if(got.begin(), got.end(), [&](const Hit& h) { return !same_bits(h, expected); });
        }
        CHECK(different_work == 0);
        CHECK(different_hits == 0);
    });
}

TEST_CASE("mixed-sign packets, +0 and -0 included, are split into octant groups that match single rays") {
    const Mesh mesh = random_soup(600, 41, 0.12f);
    const Octree tree = Octree::build(mesh, {});
    for (const Vec3f& origin : {Vec3f{0.05f, -0.1f, 0.2f}, Vec3f{-3.0f, 0.4f, 0.1f}}) {
        CAPTURE(origin.x);
        check_packets(tree, rays_of_every_sign(origin, 640, 42));
    }

    for_each_packet_arch([&]<class Arch>() {
        constexpr std::size_t width = RayPacket<Arch>::width;
        using Mask = typename RayPacket<Arch>::Mask;
        const std::vector<Ray> rays = rays_of_every_sign({0.1f, 0.2f, 0.3f}, width, 43);
        const RayPacket<Arch> packet(rays);
        const PacketRootEntry<Arch> root(packet, tree.cube());
        // The groups part the lanes; in each, the lanes crossing an axis go the mirror's way.
        std::uint32_t seen = 0;
        int groups = 0;
        for (Mask remaining = root.entered; xsimd::any(remaining); ++groups) {
            const OctantGroup<Arch> group = next_octant_group(root, remaining);
            const std::uint32_t lanes = simd::mask_bits(group.lanes);
            REQUIRE(lanes != 0);
            CHECK((lanes & seen) == 0);
            CHECK((lanes & (simd::mask_bits(remaining) & (~simd::mask_bits(remaining) + 1u))) != 0);
            seen |= lanes;
            for (int axis = 0; axis < 3; ++axis) {
                const std::uint32_t down = simd::mask_bits(root.negative[axis]);
                const std::uint32_t up = simd::mask_bits((!root.negative[axis]) & !root.parallel[axis]);
                CHECK((lanes & ((group.mirror >> axis) & 1u ? up : down)) == 0);
            }
            remaining = remaining & !group.lanes;
        }
        CHECK(seen == simd::mask_bits(root.entered));
        CHECK(groups > 1);
        // Lanes that differ only in the sign of a zero component (parallel to that axis) share
        // one group.
        std::vector<Ray> zeros(width, Ray{{0.1f, 0.2f, -3.0f}, {0.3f, 0.0f, 1.0f}});
        for (std::size_t i = 0; i < width; i += 2) zeros[i].dir.y = -0.0f;
        const RayPacket<Arch> parallel(zeros);
        const PacketRootEntry<Arch> parallel_root(parallel, tree.cube());
        CHECK(simd::mask_bits(next_octant_group(parallel_root, parallel_root.entered).lanes) ==
              simd::mask_bits(parallel_root.entered));
    });
}

TEST_CASE("lanes switched off or with an empty window come back untouched and are never occluded") {
    const Mesh mesh = random_soup(500, 51, 0.15f);
    const Octree tree = Octree::build(mesh, {});
    std::vector<Ray> rays = random_rays(mesh.bounds(), 400, 52);
    for (std::size_t i = 0; i < rays.size(); i += 7) {  // empty windows
        rays[i].tmin = 2.0f;
        rays[i].tmax = 1.0f;
    }
    SUBCASE("every third lane switched off") {
        check_packets(tree, rays, [](std::size_t lane) { return lane % 3 == 1; });
    }
    SUBCASE("all lanes but one switched off") {
        check_packets(tree, rays, [](std::size_t lane) { return lane != 2; });
    }
    SUBCASE("partial packets: fewer rays than lanes") {
        for_each_packet_arch([&]<class Arch>() {
            for (std::size_t count = 1; count < RayPacket<Arch>::width; count += 3) {
                CAPTURE(count);
                compare_packets<Arch>(tree, rays, count).require_agreement();
            }
        });
    }
}

TEST_CASE("packets of rays from inside the scene with tmin/tmax windows match single rays") {
    const Mesh mesh = random_soup(500, 61, 0.15f);
    const Octree tree = Octree::build(mesh, {});
    check_packets(tree, windowed_rays_from_inside(mesh.bounds(), 600, 62));
}

TEST_CASE("the counters count per packet: at least the busiest lane's work, at most all lanes' together") {
    const Mesh mesh = random_soup(3000, 71, 0.05f);
    const Octree tree = Octree::build(mesh, {});
    const CameraSpec camera{{0.1f, 0.2f, 3.5f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
    for_each_packet_arch([&]<class Arch>() {
        constexpr std::size_t width = RayPacket<Arch>::width;
        const std::vector<Ray> rays = pixel_block_rays(camera, 64, 36, int(width / 4), 4, 30, 72);
        PacketWorkTally tally;
        for (std::size_t first = 0; first < rays.size(); first += width) {
            const std::span<const Ray> chunk = std::span(rays).subspan(first, width);
            const RayPacket<Arch> packet(chunk);
            HitPacket<Arch> hits(packet);
            TraversalCounters one_packet;
            intersect_packet(tree, packet, hits, one_packet);
            tally.add(one_packet, chunk, [&](const Ray& ray, TraversalCounters& one_ray) {
                tree.intersect<TriangleTest::watertight>(ray, one_ray);
            });
        }
        tally.require_bounds();
    });
}

#ifdef TRIDENT_TEST_BUILTIN_SCENES
TEST_CASE("camera packets of 2x2, 4x2 and 4x4 pixel blocks on the built-in scenes match single rays") {
    for (const std::string& name : builtin_scene_names_under_test()) {
        CAPTURE(name);
        const Scene scene = make_builtin_scene(name);
        const Octree tree = Octree::build(scene.mesh, {});
        for_each_packet_arch([&]<class Arch>() {
            constexpr std::size_t width = RayPacket<Arch>::width;
            for (const auto [block_w, block_h] : {std::array{2, 2}, std::array{4, 2}, std::array{4, 4}}) {
                const std::size_t block = std::size_t(block_w * block_h);
                if (block > width) continue;
                CAPTURE(block_w);
                CAPTURE(block_h);
                const std::vector<Ray> rays = pixel_block_rays(scene.camera, 640, 360, block_w, block_h, 24, 81);
                const PacketComparison result = compare_packets<Arch>(tree, rays, block);
                CHECK(result.hits > 0);
                result.require_agreement();
            }
            // Random pixels of the same camera, and any-hit rays towards the light.
            std::vector<Ray> rays = camera_rays(scene.camera, 4 * width, 82);
            if (scene.light) {
                for (const Ray& ray : std::vector<Ray>(rays)) {
                    const Hit hit = tree.intersect(ray);
                    if (!hit.is_hit()) continue;
                    const Vec3f point = ray.origin + ray.dir * hit.t;
                    rays.push_back({point, scene.light->position - point, 1e-3f, 1.0f});
                }
            }
            compare_packets<Arch>(tree, rays).require_agreement();
        });
    }
}
#endif
