// Ray packets through the kd-tree against the single-ray traversal, at every width this machine
// runs, with the single-ray switch off, at a quarter of the width and taking every subtree: the
// same closest hit bit for bit (triangle, t, u, v; ties included, kd_packet.h says why) and the
// same any-hit answer per lane, on camera pixel blocks of the built-in scenes, incoherent,
// mixed-sign and windowed packets, packets of rays lying in split planes with +0 and -0
// components, partial packets and lanes switched off.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <span>
#include <vector>

#include "accel/kdtree/kdtree.h"
#include "kdtree/kd_test_support.h"
#include "render/image_tiles.h"
#include "scenes/builtin.h"
#include "simd/each_arch.h"
#include "support/camera_rays.h"
#include "support/packet_agreement.h"
#include "support/random_scenes.h"
#include "support/sanitizer_workload.h"

using namespace trident;
using namespace trident::testing;

namespace {

/// compare_packet_lanes() for the kd-tree's packets, with the single-ray switch at
/// `single_ray_lanes`; no ties allowed (kd_packet.h).
template <class Arch, TriangleTest Test = TriangleTest::watertight, SlabTest Slabs = SlabTest::robust>
PacketComparison compare_packets(const KdTree& tree, std::span<const Ray> rays, int single_ray_lanes,
                                 std::size_t rays_per_packet = 0, const LaneFilter& off = {}) {
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

/// Every packet width this machine runs, each with the single-ray switch off, at a quarter of the
/// width and taking every subtree, on the same rays.
template <TriangleTest Test = TriangleTest::watertight, SlabTest Slabs = SlabTest::robust>
void check_packets(const KdTree& tree, std::span<const Ray> rays, const LaneFilter& off = {},
                   std::size_t rays_per_packet = 0) {
    for_each_packet_arch([&]<class Arch>() {
        constexpr int width = int(RayPacket<Arch>::width);
        for (const PacketComparison& result :
             {compare_packets<Arch, Test, Slabs>(tree, rays, 0, rays_per_packet, off),
              compare_packets<Arch, Test, Slabs>(tree, rays, width / 4, rays_per_packet, off),
              compare_packets<Arch, Test, Slabs>(tree, rays, width, rays_per_packet, off)}) {
            CHECK(result.hits > 0);
            result.require_agreement();
        }
    });
}

/// Bundles of 16 rays through one point of a split plane, in packet order: all start on the
/// plane; in each bundle some lanes lie in the plane (direction +0 or -0 across it) and the others
/// cross it at shallow angles, of the same sign as the zero (so a bundle of +0 lanes shares an
/// octant) or of both signs. Origins sit outside the scene on one of the plane's other axes, so
/// nothing is hit at t = 0.
std::vector<Ray> split_plane_bundles(const KdTree& tree, std::size_t max_planes, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), sym(-1.0f, 1.0f);
    std::vector<SplitPlane> planes = kd_split_planes(tree);
    std::shuffle(planes.begin(), planes.end(), rng);
    planes.resize(std::min(planes.size(), max_planes));
    const Aabb box = tree.bounds();
    std::vector<Ray> rays;
    for (const SplitPlane& plane : planes) {
        const int a = plane.axis, b = (a + 1) % 3, c = (a + 2) % 3;
        for (const int kind : {0, 1, 2}) {  // +0 with positive crossings, -0 with negative, both mixed
            Vec3f origin, target;
            for (int axis = 0; axis < 3; ++axis)
                target[axis] = plane.cell.lo[axis] + unit(rng) * (plane.cell.hi[axis] - plane.cell.lo[axis]);
            origin = target;
            origin[a] = target[a] = plane.position;
            origin[b] = box.hi[b] + 1.0f + unit(rng);
            const Vec3f to_target = target - origin;
            for (int lane = 0; lane < 16; ++lane) {
                Ray ray{origin, to_target};
                ray.dir[c] += sym(rng) * 0.2f * (plane.cell.hi[c] - plane.cell.lo[c]);
                const bool negative = kind == 1 || (kind == 2 && lane % 2 == 1);
                if (lane % 3 == 0)
                    ray.dir[a] = negative ? -0.0f : 0.0f;  // lies in the plane
                else
                    ray.dir[a] = (negative ? -1.0f : 1.0f) * unit(rng) * 0.05f * length(to_target);
                rays.push_back(ray);
            }
        }
    }
    return rays;
}

}  // namespace

TEST_CASE("packets of incoherent rays find the single-ray hits at every width, with and without perfect splits") {
    const Mesh mesh = random_soup(800, 11, 0.15f);
    const std::vector<Ray> rays = random_rays(mesh.bounds(), 480, 12);  // one in five axis-parallel, +0 and -0
    for (const bool perfect : {false, true}) {
        CAPTURE(perfect);
        KdTreeOptions options;
        options.perfect_splits = perfect;
        check_packets(KdTree::build(mesh, options), rays);
    }
    // Axis-parallel rays only, grouped so that packets share their direction.
    const KdTree tree = KdTree::build(mesh);
    check_packets(tree, random_rays(mesh.bounds(), 480, 13, 1));
}

TEST_CASE("packets with the Möller-Trumbore test find its single-ray hits") {
    const Mesh mesh = random_soup(600, 21, 0.15f);
    check_packets<TriangleTest::moller_trumbore>(KdTree::build(mesh), random_rays(mesh.bounds(), 400, 22));
}

TEST_CASE("packets of rays lying in split planes, +0 and -0 mixed in, find the single-ray hits") {
    // Grid boxes: triangles lie in the split planes and edges end on them.
    const Mesh boxes = grid_boxes(60, 31);
    const Mesh soup = random_soup(1200, 32, 0.1f);
    for (const Mesh* mesh : {&boxes, &soup}) {
        for (const bool perfect : {false, true}) {
            CAPTURE(perfect);
            KdTreeOptions options;
            options.perfect_splits = perfect;
            const KdTree tree = KdTree::build(*mesh, options);
            const std::vector<Ray> rays = split_plane_bundles(tree, 60, 33);
            check_packets(tree, rays);
        }
    }
}

TEST_CASE("packets with the fast slab test find its single-ray hits, rays in split planes included") {
    const Mesh soup = random_soup(600, 23, 0.15f);
    const KdTree tree = KdTree::build(soup);
    check_packets<TriangleTest::watertight, SlabTest::fast>(tree, random_rays(soup.bounds(), 400, 24));
    check_packets<TriangleTest::moller_trumbore, SlabTest::fast>(tree,
                                                                 rays_of_every_sign({0.05f, -0.1f, 0.2f}, 640, 25));
    const Mesh boxes = grid_boxes(60, 31);
    const KdTree box_tree = KdTree::build(boxes);
    check_packets<TriangleTest::watertight, SlabTest::fast>(box_tree, split_plane_bundles(box_tree, 60, 33));
}

TEST_CASE("mixed-sign packets, +0 and -0 included, find the single-ray hits") {
    const Mesh mesh = random_soup(600, 41, 0.12f);
    const KdTree tree = KdTree::build(mesh);
    for (const Vec3f& origin : {Vec3f{0.05f, -0.1f, 0.2f}, Vec3f{-3.0f, 0.4f, 0.1f}}) {
        CAPTURE(origin.x);
        check_packets(tree, rays_of_every_sign(origin, 640, 42));
    }
}

TEST_CASE("packets of rays from inside the scene with tmin/tmax windows find the single-ray hits") {
    const Mesh mesh = random_soup(600, 61, 0.15f);
    check_packets(KdTree::build(mesh), windowed_rays_from_inside(mesh.bounds(), 600, 62));
}

TEST_CASE("lanes switched off or with an empty window come back untouched and are never occluded") {
    const Mesh mesh = random_soup(500, 51, 0.15f);
    const KdTree tree = KdTree::build(mesh);
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
    SUBCASE("every lane switched off") {
        for_each_packet_arch([&]<class Arch>() {
            const PacketComparison result = compare_packets<Arch>(tree, rays, 0, 0, [](std::size_t) { return true; });
            CHECK(result.lanes == 0);
            CHECK(result.untouched == 0);
            CHECK(result.padding == 0);
        });
    }
    SUBCASE("partial packets: fewer rays than lanes") {
        for_each_packet_arch([&]<class Arch>() {
            for (std::size_t count = 1; count < RayPacket<Arch>::width; count += 3) {
                CAPTURE(count);
                check_packets(tree, rays, {}, count);
            }
        });
    }
}

TEST_CASE("an empty kd-tree leaves every lane a miss and occludes nothing") {
    const Mesh mesh;
    const KdTree tree = KdTree::build(mesh);
    const std::vector<Ray> rays = random_rays({{-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f}}, 16, 81);
    for_each_packet_arch([&]<class Arch>() {
        const PacketComparison result = compare_packets<Arch>(tree, rays, 0);
        CHECK(result.lanes == rays.size());
        CHECK(result.hits == 0);
        CHECK(result.closest == 0);
        CHECK(result.occluded == 0);
    });
}

TEST_CASE(
    "camera pixel blocks of every built-in scene (2x2, 4x2, 4x4) and random camera rays find the single-ray hits") {
    for (const BuiltinSceneInfo& info : builtin_scenes_under_test()) {
        CAPTURE(info.name);
        const auto& [scene, tree] = builtin_kd(info.name);
        for_each_packet_arch([&]<class Arch>() {
            constexpr int width = int(RayPacket<Arch>::width);
            const auto [block_w, block_h] = packet_block(width);
            const std::vector<Ray> blocks =
                pixel_block_rays(scene.camera, 640, 360, int(block_w), int(block_h), 40, 91);
            const std::vector<Ray> random = camera_rays(scene.camera, 160, 92);
            for (const std::span<const Ray> rays : {std::span<const Ray>(blocks), std::span<const Ray>(random)}) {
                for (const PacketComparison& result :
                     {compare_packets<Arch>(tree, rays, 0), compare_packets<Arch>(tree, rays, width / 4)}) {
                    CHECK(result.hits > 0);
                    result.require_agreement();
                }
            }
        });
    }
}

TEST_CASE("the counters count per packet: at least the busiest lane's work, at most all lanes' together") {
    const auto& [scene, tree] = builtin_kd("teapot");
    for_each_packet_arch([&]<class Arch>() {
        constexpr std::size_t width = RayPacket<Arch>::width;
        const auto [block_w, block_h] = packet_block(width);
        const std::vector<Ray> rays = pixel_block_rays(scene.camera, 640, 360, int(block_w), int(block_h), 60, 101);
        PacketWorkTally tally;
        for (std::size_t first = 0; first < rays.size(); first += width) {
            const std::span<const Ray> chunk = std::span(rays).subspan(first, width);
            const RayPacket<Arch> packet(chunk);
            if (!packet.shares_octant()) continue;  // octant groups each walk the tree
            HitPacket<Arch> hits(packet);
            TraversalCounters one_packet;
            intersect_packet(tree, packet, hits, one_packet, {.single_ray_lanes = 0});
            tally.add(one_packet, chunk, [&](const Ray& ray, TraversalCounters& one_ray) {
                tree.intersect<TriangleTest::watertight>(ray, one_ray);
            });
        }
        CHECK(tally.counted > 40);
        tally.require_bounds();
    });
}

TEST_CASE("an any-hit packet retires each lane at its first hit: less work than closest hit") {
    const auto& [scene, tree] = builtin_kd("hall");
    for_each_packet_arch([&]<class Arch>() {
        constexpr std::size_t width = RayPacket<Arch>::width;
        const auto [block_w, block_h] = packet_block(width);
        const std::vector<Ray> rays = pixel_block_rays(scene.camera, 640, 360, int(block_w), int(block_h), 40, 111);
        TraversalCounters closest, any;
        for (std::size_t first = 0; first < rays.size(); first += width) {
            const RayPacket<Arch> packet(std::span<const Ray>(rays).subspan(first, width));
            HitPacket<Arch> hits(packet);
            intersect_packet(tree, packet, hits, closest, {.single_ray_lanes = 0});
            (void)occlude_packet(tree, packet, any, {.single_ray_lanes = 0});
        }
        CHECK(any.triangles_tested < closest.triangles_tested);
        CHECK(any.nodes_visited < closest.nodes_visited);
    });
}
