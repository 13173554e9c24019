// Ray packets through the octree against the single-ray traversal, at every width this machine
// runs: every lane must give the single-ray hit bit for bit (triangle, t, u, v) and the same
// any-hit answer, on coherent camera packets, incoherent and mixed-sign packets, rays along the
// octree's planes, windowed rays, partial packets and packets with lanes switched off.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "accel/octree/octree.h"
#include "octree/octree_meshes.h"
#include "octree/octree_test_support.h"
#include "simd/each_arch.h"
#include "support/camera_rays.h"
#include "support/random_scenes.h"

#if __has_include("scenes/builtin.h")
#include "scenes/builtin.h"
#define TRIDENT_TEST_BUILTIN_SCENES 1
#endif

using namespace trident;
using namespace trident::testing;

namespace {

/// Which lanes of each packet to switch off, by lane index.
using LaneFilter = std::function<bool(std::size_t)>;

struct PacketComparison {
    std::size_t lanes = 0;      // lanes compared
    std::size_t hits = 0;       // of them, single-ray hits (to see the test is not vacuous)
    std::size_t closest = 0;    // lanes whose closest hit differs in any bit
    std::size_t occluded = 0;   // lanes whose any-hit answer differs
    std::size_t untouched = 0;  // lanes not traced whose hit record changed anyway
    std::size_t padding = 0;    // lanes past the rays, reported occluded

    void require_agreement() const {
        CHECK(lanes > 0);
        CHECK(closest == 0);
        CHECK(occluded == 0);
        CHECK(untouched == 0);
        CHECK(padding == 0);
    }
};

bool same_bits(const Hit& a, const Hit& b) {
    return a.triangle == b.triangle && std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) &&
           std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
           std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v);
}

/// The raw lanes of a hit packet (misses included as they are, not as Hit{}).
template <class Arch>
struct HitLanes {
    static constexpr std::size_t width = HitPacket<Arch>::width;
    std::array<std::uint32_t, width> triangle;
    std::array<float, width> t, u, v;

    explicit HitLanes(const HitPacket<Arch>& hits) {
        hits.triangle.store_unaligned(triangle.data());
        hits.t.store_unaligned(t.data());
        hits.u.store_unaligned(u.data());
        hits.v.store_unaligned(v.data());
    }
    Hit lane(std::size_t i) const { return {triangle[i], t[i], u[i], v[i]}; }
};

/// Traces `rays` in packets of consecutive rays (the last one partial), with the lanes `off`
/// names switched off, closest hit and any hit, and compares every lane with the single-ray
/// traversal. A lane switched off, or with tmin > tmax, must keep the record it arrived with.
/// With `single_ray_lanes`, traces through traverse_octree_packet() with that switch to single
/// rays instead of the structure's members.
template <class Arch, TriangleTest Test = TriangleTest::watertight, SlabTest Slabs = SlabTest::robust>
PacketComparison compare_packets(const Octree& tree, std::span<const Ray> rays, std::size_t rays_per_packet = 0,
                                 const LaneFilter& off = {}, std::optional<int> single_ray_lanes = {}) {
    constexpr std::size_t width = RayPacket<Arch>::width;
    using Mask = typename RayPacket<Arch>::Mask;
    const std::size_t step = rays_per_packet == 0 ? width : std::min(rays_per_packet, width);
    PacketComparison out;
    NoCounters none;
    for (std::size_t first = 0; first < rays.size(); first += step) {
        const std::span<const Ray> chunk = rays.subspan(first, std::min(step, rays.size() - first));
        RayPacket<Arch> packet(chunk);
        std::array<bool, width> live{};
        for (std::size_t i = 0; i < chunk.size(); ++i) live[i] = !(off && off(i));
        packet.active = packet.active & Mask::load_unaligned(live.data());

        const HitPacket<Arch> arrived(packet);
        HitPacket<Arch> hits(packet);
        std::uint32_t occluded = 0;
        if (single_ray_lanes) {
            traverse_octree_packet<OctreeQuery::closest_hit, Test, Slabs>(tree.view(), packet, hits, none,
                                                                          *single_ray_lanes);
            HitPacket<Arch> any(packet);
            occluded = simd::mask_bits(traverse_octree_packet<OctreeQuery::any_hit, Test, Slabs>(
                tree.view(), packet, any, none, *single_ray_lanes));
        } else {
            tree.intersect<Test, Slabs>(packet, hits, none);
            occluded = simd::mask_bits(tree.occluded<Test, Slabs>(packet, none));
        }
        const HitLanes<Arch> before(arrived), after(hits);

        for (std::size_t i = 0; i < width; ++i) {
            const bool traced = i < chunk.size() && live[i] && chunk[i].tmin <= chunk[i].tmax;
            if (!traced) out.untouched += !same_bits(before.lane(i), after.lane(i));
            if (i >= chunk.size()) {
                out.padding += (occluded >> i) & 1u;
                continue;
            }
            ++out.lanes;
            const Hit expected = live[i] ? tree.intersect<Test, Slabs>(chunk[i], none) : Hit{};
            const bool expected_occluded = live[i] && tree.occluded<Test, Slabs>(chunk[i], none);
            out.hits += expected.is_hit();
            const Hit got = after.lane(i).is_hit() ? after.lane(i) : Hit{};
            out.closest += !same_bits(got, expected);
            out.occluded += bool((occluded >> i) & 1u) != expected_occluded;
        }
    }
    return out;
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

/// Primary rays of pixel blocks, `block_w` x `block_h` pixels each, in a `width` x `height` image
/// of the camera of ../shared/BENCHMARK.md, evaluated as it writes them; a block's rays are
/// consecutive, row by row. The first block sits at the image centre, the others at random.
std::vector<Ray> pixel_block_rays(const CameraSpec& camera, int width, int height, int block_w, int block_h,
                                  std::size_t blocks, std::uint32_t seed) {
    constexpr float kPi = 3.14159265358979f;
    const Vec3f forward = normalize(camera.target - camera.eye);
    const Vec3f right = normalize(cross(forward, camera.up));
    const Vec3f up = cross(right, forward);
    const float ty = std::tan(camera.fov_y_deg * kPi / 360.0f), tx = ty * float(width) / float(height);
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> column(0, width - block_w), row(0, height - block_h);
    std::vector<Ray> rays;
    for (std::size_t b = 0; b < blocks; ++b) {
        const int x0 = b == 0 ? (width - block_w) / 2 : column(rng), y0 = b == 0 ? (height - block_h) / 2 : row(rng);
        for (int y = y0; y < y0 + block_h; ++y)
            for (int x = x0; x < x0 + block_w; ++x) {
                const float sx = (2.0f * (float(x) + 0.5f) / float(width) - 1.0f) * tx;
                const float sy = (1.0f - 2.0f * (float(y) + 0.5f) / float(height)) * ty;
                rays.push_back({camera.eye, normalize(forward + sx * right + sy * up)});
            }
    }
    return rays;
}

/// Rays from `origin` whose direction components take every sign, +0 and -0 included, cycling so
/// that each packet holds lanes of several octants.
std::vector<Ray> rays_of_every_sign(const Vec3f& origin, std::size_t count, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> magnitude(0.05f, 1.0f);
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < count; ++i) {
        Vec3f d;
        for (int axis = 0; axis < 3; ++axis) {
            const std::size_t choice = (i >> (2 * axis)) % 4;  // positive, negative, +0, -0
            d[axis] = choice == 0 ? magnitude(rng) : choice == 1 ? -magnitude(rng) : choice == 2 ? 0.0f : -0.0f;
        }
        if (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f) d.x = -1.0f;
        const float zero_x = d.x;
        d = d / length(d);
        if (zero_x == 0.0f) d.x = zero_x;  // keep the sign of a zero
        rays.push_back({origin, d});
    }
    return rays;
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
            tree.intersect<TriangleTest::watertight>(packet, hits, packed);
            tree.occluded<TriangleTest::watertight>(ray, single_any);
            tree.occluded<TriangleTest::watertight>(packet, packed_any);
            different_work += single.nodes_visited != packed.nodes_visited ||
                              single.triangles_tested != packed.triangles_tested ||
                              single_any.nodes_visited != packed_any.nodes_visited ||
                              single_any.triangles_tested != packed_any.triangles_tested;
            std::array<Hit, RayPacket<Arch>::width> got;
            hits.store(got);
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
        TraversalCounters packets, lanes;
        std::size_t below_busiest = 0, above_sum = 0;
        for (std::size_t first = 0; first < rays.size(); first += width) {
            const std::span<const Ray> chunk = std::span(rays).subspan(first, width);
            const RayPacket<Arch> packet(chunk);
            HitPacket<Arch> hits(packet);
            TraversalCounters one_packet, busiest, sum;
            tree.intersect<TriangleTest::watertight>(packet, hits, one_packet);
            for (const Ray& ray : chunk) {
                TraversalCounters one;
                tree.intersect<TriangleTest::watertight>(ray, one);
                busiest.nodes_visited = std::max(busiest.nodes_visited, one.nodes_visited);
                busiest.triangles_tested = std::max(busiest.triangles_tested, one.triangles_tested);
                sum += one;
            }
            below_busiest += one_packet.nodes_visited < busiest.nodes_visited ||
                             one_packet.triangles_tested < busiest.triangles_tested;
            above_sum +=
                one_packet.nodes_visited > sum.nodes_visited || one_packet.triangles_tested > sum.triangles_tested;
            packets += one_packet;
            lanes += sum;
        }
        CHECK(below_busiest == 0);
        CHECK(above_sum == 0);
        // The point of packets: coherent lanes share most of their nodes.
        CHECK(2 * packets.nodes_visited < lanes.nodes_visited);
    });
}

#ifdef TRIDENT_TEST_BUILTIN_SCENES
TEST_CASE("camera packets of 2x2, 4x2 and 4x4 pixel blocks on the built-in scenes match single rays") {
    for (const std::string& name : builtin_scene_names()) {
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
