// The wide BVH (accel/bvh/wide_bvh.h) at each width and block size it ships: its layout holds
// every triangle with area once (and no zero-area one) with its exact corners inside its boxes; single rays find the
// binary BVH's closest t bit for bit and the double-precision reference's hits; any hit agrees with closest hit; and
// packets of every width give each lane the wide single ray's hit bit for bit (the tie rule makes the answer
// independent of the visiting order, so no tie is allowed).
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <span>
#include <vector>

#include "accel/bvh/wide_bvh.h"
#include "accel/bvh/wide_collapse.h"
#include "accel/bvh/wide_packet.h"
#include "bvh_test_helpers.h"
#include "simd/each_arch.h"
#include "support/packet_agreement.h"
#include "support/random_scenes.h"
#include "support/reference_check.h"
#include "support/sanitizer_workload.h"

using namespace trident;
using namespace trident::testing;

namespace {

/// The layout's promises, checked against the mesh.
template <std::size_t Width, std::size_t BlockSize>
void check_layout(const WideBvh<Width, BlockSize>& wide, const Mesh& mesh) {
    using Tree = WideBvh<Width, BlockSize>;
    const auto nodes = wide.nodes();
    const auto blocks = wide.blocks();
    const std::size_t n = mesh.triangle_count();
    REQUIRE(nodes.empty() == (n == 0));
    std::vector<int> seen(n, 0), node_seen(nodes.size(), 0), with_area(n);
    std::vector<std::size_t> node_depth(nodes.size(), 0);
    for (std::size_t i = 0; i < n; ++i) with_area[i] = has_area(triangle_of(mesh, i));
    const auto stored = std::size_t(std::count(with_area.begin(), with_area.end(), 1));
    // Spatial splits put a cut triangle in each leaf its pieces reached, each leaf's box around its pieces.
    const bool spatial = wide.options().builder == BvhBuilder::spatial_sah;
    std::size_t wrong_corners = 0, outside_box = 0, unpacked_slots = 0, padding_differs = 0, leaves = 0, max_depth = 0,
                children = 0, repeated_in_leaf = 0, references = 0;
    auto walk = [&](auto&& self, std::uint32_t index, std::size_t depth) -> void {
        REQUIRE(index < nodes.size());
        ++node_seen[index];
        node_depth[index] = depth;
        const typename Tree::Node& node = nodes[index];
        bool empty_seen = false;
        for (std::size_t k = 0; k < Width; ++k) {
            const bvh::ChildRef ref = node.child[k];
            if (ref.is_empty()) {
                empty_seen = true;
                continue;
            }
            unpacked_slots += empty_seen;
            ++children;
            Aabb box;
            box.lo = {node.bounds[bvh::lower_row(0)][k], node.bounds[bvh::lower_row(1)][k],
                      node.bounds[bvh::lower_row(2)][k]};
            box.hi = {node.bounds[bvh::upper_row(0)][k], node.bounds[bvh::upper_row(1)][k],
                      node.bounds[bvh::upper_row(2)][k]};
            if (!ref.is_leaf()) {
                // A node's byte offset in the node array: a whole node from its start.
                REQUIRE(ref.node_offset() % sizeof(typename Tree::Node) == 0);
                self(self, std::uint32_t(ref.node_offset() / sizeof(typename Tree::Node)), depth + 1);
                continue;
            }
            ++leaves;
            max_depth = std::max(max_depth, depth + 1);
            REQUIRE(ref.first_block() + ref.template block_count<BlockSize>() <= blocks.size());
            for (std::uint32_t lane = 0; lane < ref.template block_count<BlockSize>() * BlockSize; ++lane) {
                const auto& block = blocks[ref.first_block() + lane / BlockSize];
                const std::size_t i = lane % BlockSize;
                const Triangle tri{{block.a[0][i], block.a[1][i], block.a[2][i]},
                                   {block.b[0][i], block.b[1][i], block.b[2][i]},
                                   {block.c[0][i], block.c[1][i], block.c[2][i]}};
                REQUIRE(block.id[i] < n);
                const Triangle expected = triangle_of(mesh, block.id[i]);
                wrong_corners += !(tri.a == expected.a && tri.b == expected.b && tri.c == expected.c);
                const Aabb tri_box = tri.bounds();
                outside_box += spatial ? Aabb{max(tri_box.lo, box.lo), min(tri_box.hi, box.hi)}.is_empty()
                                       : !box.contains(tri_box);
                if (lane < ref.triangle_count()) {
                    ++seen[block.id[i]];
                    ++references;
                    for (std::uint32_t earlier = 0; earlier < lane; ++earlier)
                        repeated_in_leaf +=
                            blocks[ref.first_block() + earlier / BlockSize].id[earlier % BlockSize] == block.id[i];
                } else {  // padding repeats the leaf's last triangle
                    const auto& last = blocks[ref.first_block() + (ref.triangle_count() - 1) / BlockSize];
                    padding_differs += block.id[i] != last.id[(ref.triangle_count() - 1) % BlockSize];
                }
            }
        }
    };
    if (!nodes.empty()) walk(walk, 0, 0);
    // Numbered breadth-first: a level's nodes follow the level above, so the first levels are the
    // first nodes and the packet switch's offset bound on the level (wide_packet_switch) holds.
    CHECK(std::is_sorted(node_depth.begin(), node_depth.end()));
    for (std::size_t levels = 0; levels <= max_depth + 1; ++levels) {
        CAPTURE(levels);
        const auto above = std::size_t(
            std::count_if(node_depth.begin(), node_depth.end(), [&](std::size_t d) { return d < levels; }));
        CHECK(bvh::nodes_above_level<Width>(nodes, levels) == above);
        if (levels == kIncoherentLaneUseLevels) CHECK(wide.lane_use_end() == above * sizeof(typename Tree::Node));
    }
    CHECK(wrong_corners == 0);
    CHECK(outside_box == 0);
    CHECK(unpacked_slots == 0);
    CHECK(padding_differs == 0);
    CHECK(repeated_in_leaf == 0);
    if (spatial) {  // each triangle with area at least once, none without
        for (std::size_t i = 0; i < n; ++i) seen[i] = seen[i] != 0;
        CHECK(seen == with_area);
    } else {
        CHECK(seen == with_area);  // each triangle with area once, none without
    }
    CHECK(std::count(node_seen.begin(), node_seen.end(), 1) == std::ptrdiff_t(nodes.size()));
    const AccelStats& stats = wide.stats();
    CHECK(stats.triangles == n);
    CHECK(stats.leaves == leaves);
    CHECK(stats.nodes == nodes.size() + leaves);
    CHECK(stats.max_depth == max_depth);
    CHECK(stats.references == references);
    if (!spatial) CHECK(references == stored);
    CHECK(stats.bytes == nodes.size() * sizeof(typename Tree::Node) + blocks.size() * sizeof(typename Tree::Block));
    if (!nodes.empty()) CHECK(stats.mean_children == doctest::Approx(double(children) / double(nodes.size())));
    if (!blocks.empty()) {
        CHECK(stats.block_fill == doctest::Approx(double(references) / double(blocks.size() * BlockSize)));
        CHECK(stats.block_fill > 0.0);
        CHECK(stats.block_fill <= 1.0);
    }
}

/// Single rays: closest t bit for bit the binary BVH's (the same tree's triangles, whichever
/// triangle of a tie), the reference's hits, and any hit where closest hit finds one.
template <std::size_t Width, std::size_t BlockSize, TriangleTest Test = TriangleTest::watertight,
          SlabTest Slabs = SlabTest::robust>
void check_single_rays(const WideBvh<Width, BlockSize>& wide, const Bvh& binary, const Mesh& mesh,
                       std::span<const Ray> rays) {
    NoCounters none;
    std::vector<Hit> hits;
    std::size_t t_differs = 0, occluded_differs = 0, found = 0, hinted_differs = 0;
    for (const Ray& ray : rays) {
        const Hit hit = wide.template intersect<Test, Slabs>(ray, none);
        const Hit expected = binary.intersect<Test, Slabs>(ray, none);
        t_differs += hit.is_hit() != expected.is_hit() || (hit.is_hit() && !same_bits(hit.t, expected.t));
        occluded_differs += wide.template occluded<Test, Slabs>(ray, none) != hit.is_hit();
        // The incoherent walk (which prefetches what it stacks) finds the same hit, bit for bit.
        const Hit hinted = wide.template intersect<Test, Slabs>(ray, none, RayCoherence::incoherent);
        hinted_differs += !same_bits(hinted, hit);
        found += hit.is_hit();
        hits.push_back(hit);
    }
    CHECK(found > 0);
    CHECK(t_differs == 0);
    CHECK(occluded_differs == 0);
    CHECK(hinted_differs == 0);
    if constexpr (Test == TriangleTest::watertight && Slabs == SlabTest::robust) {
        const std::vector<Triangle> triangles = gather_triangles(mesh);
        require_agreement(compare_with_reference<Hit>(triangles, rays, hits));
    }
}

/// Packets of every width this machine runs, with the single-ray switch off, at 1 lane, at every
/// lane and at the structure's own choice, against the wide single ray; no tie allowed.
template <std::size_t Width, std::size_t BlockSize, TriangleTest Test = TriangleTest::watertight,
          SlabTest Slabs = SlabTest::robust>
void check_packets(const WideBvh<Width, BlockSize>& wide, std::span<const Ray> rays, const LaneFilter& off = {}) {
    NoCounters none;
    for_each_packet_arch([&]<class Arch>() {
        constexpr int lanes = int(RayPacket<Arch>::width);
        for (const int single_ray_lanes : {0, 1, lanes, kDefaultSingleRayLanes}) {
            CAPTURE(single_ray_lanes);
            const PacketVariant variant{.test = Test, .slabs = Slabs, .single_ray_lanes = single_ray_lanes};
            compare_packet_lanes<Arch>(
                rays, 0, off,
                [&](const RayPacket<Arch>& packet, HitPacket<Arch>& hits) {
                    intersect_packet(wide, packet, hits, none, variant);
                    return simd::mask_bits(occlude_packet(wide, packet, none, variant));
                },
                [&](const Ray& ray) { return wide.template intersect<Test, Slabs>(ray, none); },
                [&](const Ray& ray) { return wide.template occluded<Test, Slabs>(ray, none); })
                .require_agreement();
        }
    });
}

/// Shadow rays with the last occluder tried first (LastOccluder), carried from ray to ray and from
/// packet to packet, or set to a block at random before each: the answers stay occluded()'s lane
/// for lane, and after a single ray it names a block (one of the tree's) exactly when that ray was
/// stopped.
template <std::size_t Width, std::size_t BlockSize>
void check_last_occluder(const WideBvh<Width, BlockSize>& wide, std::span<const Ray> rays) {
    REQUIRE_FALSE(wide.blocks().empty());
    NoCounters none;
    std::mt19937 rng(71);
    std::uniform_int_distribution<std::uint32_t> any_block(0, std::uint32_t(wide.blocks().size() - 1));
    std::size_t stopped = 0;
    for (const bool at_random : {false, true}) {
        CAPTURE(at_random);
        LastOccluder last;
        std::size_t differ = 0, named_wrongly = 0, counted_wrongly = 0;
        for (const Ray& ray : rays) {
            if (at_random) last.id = any_block(rng);
            const bool got = wide.template occluded<TriangleTest::watertight>(ray, none, last);
            differ += got != wide.occluded(ray);
            named_wrongly += got != (last.id != LastOccluder::kNone) ||
                             (last.id != LastOccluder::kNone && last.id >= wide.blocks().size());
            stopped += got;
            if (got && last.id < wide.blocks().size()) {
                // The same ray again stops at the block it names, counted as the walk counts a
                // block: its real triangles, not the lanes repeating the last one.
                const auto& ids = wide.blocks()[last.id].id;
                std::size_t real = 0;
                for (std::size_t k = 0; k < BlockSize; ++k) real += k == 0 || ids[k] != ids[k - 1];
                LastOccluder again = last;
                TraversalCounters counted;
                CHECK(wide.template occluded<TriangleTest::watertight>(ray, counted, again));
                counted_wrongly += counted.triangles_tested != real || counted.nodes_visited != 0;
            }
        }
        CHECK(differ == 0);
        CHECK(named_wrongly == 0);
        CHECK(counted_wrongly == 0);
        for_each_packet_arch([&]<class Arch>() {
            LastOccluder carried;
            compare_packet_lanes<Arch>(
                rays, 0, {},
                [&](const RayPacket<Arch>& packet, HitPacket<Arch>& hits) {
                    intersect_packet(wide, packet, hits, none);
                    if (at_random) carried.id = any_block(rng);
                    const auto bits = simd::mask_bits(occlude_packet(wide, packet, none, PacketVariant{}, &carried));
                    CHECK((carried.id == LastOccluder::kNone || carried.id < wide.blocks().size()));
                    return bits;
                },
                [&](const Ray& ray) { return wide.intersect(ray); }, [&](const Ray& ray) { return wide.occluded(ray); })
                .require_agreement();
        });
    }
    CHECK(stopped > rays.size() / 4);  // the rays exercise the cache
}

/// Every shipped width and block size, one body.
template <class Body>
void for_each_wide_tree(const Mesh& mesh, const BvhOptions& options, Body&& body) {
    body(WideBvh<4, 4>::build(mesh, options));
    body(WideBvh<8, 4>::build(mesh, options));
    body(WideBvh<16, 4>::build(mesh, options));
}

}  // namespace

TEST_CASE("the wide layout holds every triangle once, inside its boxes, for every builder setting") {
    BvhOptions sweep;
    sweep.builder = BvhBuilder::sweep_sah;
    BvhOptions one_per_leaf;
    one_per_leaf.max_leaf_size = 1;
    BvhOptions large_leaves;
    large_leaves.max_leaf_size = 40;
    large_leaves.intersection_cost = 0.05f;  // the binary builder then keeps leaves of up to 40
    BvhOptions spatial;
    spatial.builder = BvhBuilder::spatial_sah;
    for (const std::size_t count : {1, 3, 17, 600}) {
        const Mesh mesh = random_soup(count, 7 + std::uint32_t(count), 0.15f);
        for (const BvhOptions& options : {BvhOptions{}, sweep, one_per_leaf, large_leaves, spatial}) {
            CAPTURE(count);
            CAPTURE(options.max_leaf_size);
            for_each_wide_tree(mesh, options, [&](const auto& wide) { check_layout(wide, mesh); });
        }
    }
    for_each_wide_tree(builtin_scene("teapot").mesh, {}, [&](const auto& wide) {
        check_layout(wide, builtin_scene("teapot").mesh);
        CHECK(wide.stats().mean_children > 2.5);  // wide in fact, not a binary tree in disguise
    });
}

TEST_CASE("in the smallest subtrees the collapse keeps one fuller block rather than two leaves of a few triangles") {
    // Two unit quads 2 apart (a 4x1 strip whose quads' boxes hold half its area: the binary tree
    // splits it), scaled by `scale`, and a unit triangle 2 above them.
    const auto quads_and_triangle = [](float scale) {
        Mesh mesh;
        for (const float x : {0.0f, 3.0f}) {
            const auto a = mesh.add_vertex(Vec3f{x, 0, 0} * scale), b = mesh.add_vertex(Vec3f{x + 1, 0, 0} * scale);
            const auto c = mesh.add_vertex(Vec3f{x + 1, 1, 0} * scale), d = mesh.add_vertex(Vec3f{x, 1, 0} * scale);
            mesh.add_triangle(a, b, c);
            mesh.add_triangle(a, c, d);
        }
        mesh.add_triangle(mesh.add_vertex({0, 0, 2}), mesh.add_vertex({1, 0, 2}), mesh.add_vertex({0, 1, 2}));
        return mesh;
    };
    // At full size a leaf a quad saves the strip's rays half their block tests: three leaves.
    for_each_wide_tree(quads_and_triangle(1.0f), {}, [&](const auto& wide) {
        check_layout(wide, quads_and_triangle(1.0f));
        CHECK(wide.stats().leaves == 3);
    });
    // A thousandth of the size, the strip's area is a millionth of the root's: what a second block
    // saves its rays is less than the block's memory costs, so the strip is one leaf of one block.
    for_each_wide_tree(quads_and_triangle(1e-3f), {}, [&](const auto& wide) {
        check_layout(wide, quads_and_triangle(1e-3f));
        CHECK(wide.stats().leaves == 2);
        CHECK(wide.blocks().size() == 2);
    });
}

TEST_CASE("zero-area triangles are left out of the blocks and never hit, as the binary tree never hits them") {
    // Points and segments among real triangles, and a mesh of nothing else (leaves without blocks).
    Mesh mixed = random_soup(300, 41, 0.15f), degenerate;
    for (int i = 0; i < 200; ++i) {
        // Binary fractions, so that the segments' corners are collinear in float too.
        const float x = float(i % 20) * 0.0625f, y = float(i / 20) * 0.125f;
        const Vec3f p{x, y, 0.5f}, q{x + 0.125f, y + 0.0625f, 0.5f}, r{x + 0.25f, y + 0.125f, 0.5f};
        for (Mesh* mesh : {&mixed, &degenerate}) {
            const std::uint32_t point = mesh->add_vertex(p);
            mesh->add_triangle(point, point, point);
            mesh->add_triangle(mesh->add_vertex(p), mesh->add_vertex(q), mesh->add_vertex(r));  // a segment
        }
    }
    const std::vector<Ray> rays = random_rays(mixed.bounds(), 400, 42);
    const Bvh binary = Bvh::build(mixed);
    for_each_wide_tree(mixed, {}, [&](const auto& wide) {
        check_layout(wide, mixed);
        CHECK(wide.stats().references == 300);
        check_single_rays(wide, binary, mixed, rays);
        check_packets(wide, rays);
    });
    for_each_wide_tree(degenerate, {}, [&](const auto& wide) {
        check_layout(wide, degenerate);
        CHECK(wide.blocks().empty());
        CHECK_FALSE(wide.nodes().empty());
        for (const Ray& ray : random_rays(degenerate.bounds(), 200, 43)) {
            CHECK_FALSE(wide.intersect(ray).is_hit());
            CHECK_FALSE(wide.occluded(ray));
        }
    });
}

TEST_CASE("an empty mesh gives a wide tree that every ray misses") {
    const Mesh empty;
    for_each_wide_tree(empty, {}, [&](const auto& wide) {
        CHECK(wide.nodes().empty());
        const Ray ray{{0, 0, -1}, {0, 0, 1}};
        CHECK_FALSE(wide.intersect(ray).is_hit());
        CHECK_FALSE(wide.occluded(ray));
    });
}

TEST_CASE("wide single rays find the binary tree's closest t and the reference's hits") {
    const Mesh soup = random_soup(800, 31, 0.15f);
    const std::vector<Ray> rays = random_rays(soup.bounds(), 500, 32);
    const Bvh binary = Bvh::build(soup);
    for_each_wide_tree(soup, {}, [&](const auto& wide) {
        check_single_rays(wide, binary, soup, rays);
        check_single_rays<std::decay_t<decltype(wide)>::width, std::decay_t<decltype(wide)>::block_size,
                          TriangleTest::moller_trumbore>(wide, binary, soup, rays);
        check_single_rays<std::decay_t<decltype(wide)>::width, std::decay_t<decltype(wide)>::block_size,
                          TriangleTest::watertight, SlabTest::fast>(wide, binary, soup, rays);
    });
    const Mesh lattice = axis_lattice();
    const Bvh lattice_binary = Bvh::build(lattice);
    const std::vector<Ray> plane_rays = rays_on_lattice_planes();
    for_each_wide_tree(lattice, {},
                       [&](const auto& wide) { check_single_rays(wide, lattice_binary, lattice, plane_rays); });
    const Mesh& teapot = builtin_scene("teapot").mesh;
    const std::vector<Ray> camera = camera_rays(builtin_scene("teapot").camera, 1500, 33);
    for_each_wide_tree(teapot, {},
                       [&](const auto& wide) { check_single_rays(wide, builtin_bvh("teapot"), teapot, camera); });
}

TEST_CASE("the limit just past a hit is the next float up, -0 counting as 0") {
    std::mt19937 rng(71);
    std::uniform_int_distribution<std::uint32_t> finite_non_negative(0u, 0x7f7fffffu);
    for (int i = 0; i < 100000; ++i) {
        const float t = std::bit_cast<float>(finite_non_negative(rng));
        REQUIRE(same_bits(bvh::just_above(t), std::nextafter(t, kInfinity)));
        REQUIRE(same_bits(bvh::just_above(xsimd::batch<float>(t)).get(0), bvh::just_above(t)));  // a packet's lanes
    }
    for (const float t :
         {0.0f, -0.0f, std::numeric_limits<float>::denorm_min(), 1.0f, std::numeric_limits<float>::max()}) {
        CHECK(same_bits(bvh::just_above(t), std::nextafter(t, kInfinity)));
        CHECK(same_bits(bvh::just_above(xsimd::batch<float>(t)).get(0), bvh::just_above(t)));
    }
    CHECK(bvh::triangle_limit(Hit{}) == kInfinity);  // nothing hit: the ray's tmax
}

TEST_CASE("at equal t the lowest triangle id wins, whatever the order") {
    // Two copies of one triangle far apart in the file: every order of visiting must keep id 0.
    Mesh mesh = random_soup(300, 41, 0.1f);
    const Triangle first = triangle_of(mesh, 0);
    mesh.add_triangle(mesh.add_vertex(first.a), mesh.add_vertex(first.b), mesh.add_vertex(first.c));
    const Vec3f centre = first.centroid();
    const Ray ray{centre - Vec3f{0.0f, 0.0f, 3.0f}, {0.0f, 0.0f, 1.0f}};
    for_each_wide_tree(mesh, {}, [&](const auto& wide) {
        const Hit hit = wide.intersect(ray);
        REQUIRE(hit.is_hit());
        TriangleHit h;
        if (TriangleIntersector<TriangleTest::watertight>(ray).intersect(first, kInfinity, h) && same_bits(h.t, hit.t))
            CHECK(hit.triangle == 0);
    });
}

TEST_CASE(
    "over spatial splits the wide tree keeps its layout, the binary tree's closest t, and packets equal to single "
    "rays") {
    const Mesh soup = soup_with_large_triangles(1500, 20, 61);
    BvhOptions spatial;
    spatial.builder = BvhBuilder::spatial_sah;
    const Bvh binary = Bvh::build(soup);
    std::vector<Ray> rays = random_rays(soup.bounds(), 500, 62);
    for (const Ray& r : random_rays(soup.bounds(), 200, 63, 1)) rays.push_back(r);  // axis-parallel
    for_each_wide_tree(soup, spatial, [&](const auto& wide) {
        check_layout(wide, soup);
        CHECK(wide.stats().references > soup.triangle_count());  // triangles were cut
        check_single_rays(wide, binary, soup, rays);
        check_packets(wide, rays);
    });
}

/// Rays from one point below the box on every axis (so of one octant) to points of the box:
/// packets of them walk by the frustum alone (wide_packet.h). `grid` > 0 aims them at the points
/// of a grid of that many cells a side through the box (on a lattice: its edges and vertices);
/// otherwise at random points.
std::vector<Ray> rays_from_one_point(const Aabb& box, std::size_t count, unsigned seed, int grid = 0) {
    const Vec3f extent = box.extent();
    const Vec3f origin = box.lo - 0.75f * extent;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::uniform_int_distribution<int> cell(0, std::max(grid, 1));
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < count; ++i) {
        Vec3f target;
        for (int axis = 0; axis < 3; ++axis) {
            const float share = grid > 0 ? float(cell(rng)) / float(grid) : unit(rng);
            target[axis] = box.lo[axis] + share * extent[axis];
        }
        rays.push_back(Ray{origin, target - origin});
    }
    return rays;
}

TEST_CASE("packets from one point walk by the frustum alone and give every lane the single ray's hit") {
    const Mesh soup = random_soup(700, 57, 0.15f);
    const Mesh lattice = axis_lattice();
    for_each_packet_arch([&]<class Arch>() {  // such packets are the ones that take the frustum alone
        const std::vector<Ray> rays = rays_from_one_point(soup.bounds(), RayPacket<Arch>::width, 64);
        const RayPacket<Arch> packet(rays);
        const auto group = bvh::RayGroupBounds::of(packet, packet.active);
        REQUIRE(group.has_value());
        CHECK(group->shares_origin());
        std::vector<Ray> moved = rays;  // one origin moved: the lane tests again
        moved.back().origin.x += 1.0f;
        const auto moved_group = bvh::RayGroupBounds::of(RayPacket<Arch>(moved), packet.active);
        REQUIRE(moved_group.has_value());
        CHECK_FALSE(moved_group->shares_origin());
    });
    // A quarter of the rays under the sanitizers (support/sanitizer_workload.h): still 5 to 10
    // packets of 16 lanes per call.
    const std::size_t many = testing::workload(640, 4), some = testing::workload(320, 4);
    for_each_wide_tree(soup, {}, [&](const auto& wide) {
        using Tree = std::decay_t<decltype(wide)>;
        check_packets(wide, rays_from_one_point(soup.bounds(), many, 58));
        check_packets<Tree::width, Tree::block_size, TriangleTest::moller_trumbore>(
            wide, rays_from_one_point(soup.bounds(), some, 59));
        check_packets(wide, rays_from_one_point(soup.bounds(), some, 60),
                      [](std::size_t lane) { return lane % 3 == 1; });
    });
    for_each_wide_tree(lattice, {}, [&](const auto& wide) {
        check_packets(wide, rays_from_one_point(lattice.bounds(), many, 61, 8));  // through edges and vertices
    });
    BvhOptions spatial;
    spatial.builder = BvhBuilder::spatial_sah;
    const Mesh large = soup_with_large_triangles(1500, 20, 62);
    for_each_wide_tree(large, spatial,
                       [&](const auto& wide) { check_packets(wide, rays_from_one_point(large.bounds(), many, 63)); });
}

TEST_CASE("wide packets give every lane the wide single ray's hit bit for bit") {
    const Mesh soup = random_soup(700, 51, 0.15f);
    // A quarter of the rays under the sanitizers (support/sanitizer_workload.h).
    const std::vector<Ray> incoherent = random_rays(soup.bounds(), testing::workload(400, 4), 52);
    const std::vector<Ray> every_sign = rays_of_every_sign({0.05f, -0.1f, 0.2f}, testing::workload(640, 4), 53);
    const std::vector<Ray> windowed = windowed_rays_from_inside(soup.bounds(), testing::workload(400, 4), 54);
    for_each_wide_tree(soup, {}, [&](const auto& wide) {
        using Tree = std::decay_t<decltype(wide)>;
        check_packets(wide, incoherent);
        check_packets(wide, every_sign);
        check_packets(wide, windowed);
        check_packets<Tree::width, Tree::block_size, TriangleTest::moller_trumbore>(wide, incoherent);
        check_packets<Tree::width, Tree::block_size, TriangleTest::watertight, SlabTest::fast>(wide, every_sign);
        check_packets(wide, incoherent, [](std::size_t lane) { return lane % 3 == 1; });
    });
    const Mesh lattice = axis_lattice();
    const std::vector<Ray> plane_rays = rays_on_lattice_planes();
    std::vector<Ray> shuffled = plane_rays;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(5));
    for_each_wide_tree(lattice, {}, [&](const auto& wide) {
        check_packets(wide, plane_rays);
        check_packets(wide, shuffled);
    });
    const Scene& teapot = builtin_scene("teapot");
    const std::vector<Ray> blocks = pixel_block_rays(teapot.camera, 320, 180, 4, 4, testing::workload(200, 4), 55);
    for_each_wide_tree(teapot.mesh, {}, [&](const auto& wide) { check_packets(wide, blocks); });
    // Over a tree this large, incoherent packets go alone from the root (wide_packet_switch). Built
    // binned: the switch depends on the block count, not the builder, and the default's spatial
    // splits of 40,960 triangles were a fifth of this case's time under the sanitizers.
    const Mesh many = random_soup(5 * kIncoherentAloneMinBlocks, 56, 0.02f);
    const std::vector<Ray> through_many = random_rays(many.bounds(), testing::workload(200, 4), 57);
    BvhOptions binned;
    binned.builder = BvhBuilder::binned_sah;
    for_each_wide_tree(many, binned, [&](const auto& wide) {
        REQUIRE(wide.blocks().size() >= kIncoherentAloneMinBlocks);
        check_packets(wide, through_many);
    });
}

TEST_CASE(
    "by default only a packet whose directions spread beyond the cone switches to single rays: over a large tree "
    "from the root, over a small one where its lanes part") {
    for_each_packet_arch([&]<class Arch>() {
        // Every lane along (1, 0, 0) but lane 1, turned by `degrees` in the xy plane, and scaled:
        // the test takes directions of any length.
        const auto packet_turned_by = [](float degrees, std::size_t live = RayPacket<Arch>::width) {
            const float radians = degrees * 3.14159265f / 180.0f;
            std::vector<Ray> rays(live, Ray{{0, 0, 0}, {2.0f, 0.0f, 0.0f}, 0.0f, kInfinity});
            rays[1].dir = {0.5f * std::cos(radians), 0.5f * std::sin(radians), 0.0f};
            return RayPacket<Arch>(std::span<const Ray>(rays));
        };
        CHECK(bvh::directions_within_cone(packet_turned_by(0.0f), kCoherentCosine));
        CHECK(bvh::directions_within_cone(packet_turned_by(20.0f), kCoherentCosine));
        CHECK_FALSE(bvh::directions_within_cone(packet_turned_by(40.0f), kCoherentCosine));
        CHECK_FALSE(bvh::directions_within_cone(packet_turned_by(180.0f), kCoherentCosine));
        constexpr std::size_t kSmallTree = kIncoherentAloneMinBlocks - 1, kLargeTree = kIncoherentAloneMinBlocks;
        constexpr std::uint32_t kLaneUseEnd = 5 * 1024;  // a tree's offset past its first levels' nodes
        for (const std::size_t blocks : {kSmallTree, kLargeTree}) {
            const bvh::PacketSwitch coherent =
                wide_packet_switch(packet_turned_by(20.0f), kDefaultSingleRayLanes, blocks, kLaneUseEnd);
            const bvh::PacketSwitch asked = wide_packet_switch(packet_turned_by(40.0f), 3, blocks, kLaneUseEnd);
            CHECK(coherent.single_ray_lanes == kWideSingleRayLanes);
            CHECK(coherent.min_lane_use == 0.0f);
            CHECK(coherent.lane_use_end == 0);
            CHECK(coherent.coherence == RayCoherence::coherent);
            CHECK(asked.single_ray_lanes == 3);
            CHECK(asked.min_lane_use == 0.0f);
            CHECK(asked.lane_use_end == 0);
            CHECK(asked.coherence == RayCoherence::coherent);
        }
        const bvh::PacketSwitch spread_small =
            wide_packet_switch(packet_turned_by(40.0f), kDefaultSingleRayLanes, kSmallTree, kLaneUseEnd);
        CHECK(spread_small.single_ray_lanes == kWideSingleRayLanes);
        CHECK(spread_small.min_lane_use == kIncoherentMinLaneUse);
        CHECK(spread_small.lane_use_end == kLaneUseEnd);
        CHECK(spread_small.coherence == RayCoherence::incoherent);
        const bvh::PacketSwitch spread_large =
            wide_packet_switch(packet_turned_by(40.0f), kDefaultSingleRayLanes, kLargeTree, kLaneUseEnd);
        CHECK(spread_large.single_ray_lanes == int(RayPacket<Arch>::width));
        CHECK(spread_large.min_lane_use == 0.0f);
        CHECK(spread_large.lane_use_end == 0);
        CHECK(spread_large.coherence == RayCoherence::incoherent);
        // Two lanes opposite each other: the second lies outside every cone around the first.
        CHECK_FALSE(bvh::directions_within_cone(packet_turned_by(180.0f, 2), kCoherentCosine));
        // Lanes past the rays copy the first ray and count for nothing.
        CHECK(bvh::directions_within_cone(packet_turned_by(20.0f, 2), kCoherentCosine));
    });
}

TEST_CASE("the last occluder tried first changes no shadow ray's answer, whatever block it names") {
    const Mesh soup = random_soup(700, 81, 0.15f);
    std::vector<Ray> rays = random_rays(soup.bounds(), 300, 82);
    for (const Ray& r : windowed_rays_from_inside(soup.bounds(), 300, 83)) rays.push_back(r);
    for (const Ray& r : rays_from_one_point(soup.bounds(), 320, 84)) rays.push_back(r);
    for_each_wide_tree(soup, {}, [&](const auto& wide) { check_last_occluder(wide, rays); });
    const Mesh lattice = axis_lattice();  // rays along faces and edges shared by neighbours
    for_each_wide_tree(lattice, {}, [&](const auto& wide) { check_last_occluder(wide, rays_on_lattice_planes()); });
}

TEST_CASE("the cone test gives the same answer over a packet's lanes and over the rays it is built from") {
    // Lane 1 turned by `degrees` from the others, `live` rays.
    const auto turned_by = [](float degrees, std::size_t live) {
        const float radians = degrees * 3.14159265f / 180.0f;
        std::vector<Ray> rays(live, Ray{{0, 0, 0}, {2.0f, 0.0f, 0.0f}, 0.0f, kInfinity});
        rays[1].dir = {0.5f * std::cos(radians), 0.5f * std::sin(radians), 0.0f};
        return rays;
    };
    for_each_packet_arch([&]<class Arch>() {
        for (const float degrees : {0.0f, 20.0f, 25.0f, 26.0f, 40.0f, 90.0f, 180.0f})
            for (const std::size_t live : {std::size_t(2), RayPacket<Arch>::width}) {
                CAPTURE(degrees);
                CAPTURE(live);
                const std::vector<Ray> rays = turned_by(degrees, live);
                const bool within = bvh::directions_within_cone(
                    rays.size(), [&](std::size_t k) { return rays[k].dir; }, kCoherentCosine);
                CHECK(within ==
                      bvh::directions_within_cone(RayPacket<Arch>(std::span<const Ray>(rays)), kCoherentCosine));
                CHECK(within == (degrees <= 25.0f));  // the cone's half-angle: acos(0.9), 25.8 degrees
                std::vector<std::size_t> reversed(live);  // the packet's rays read through an index
                std::iota(reversed.rbegin(), reversed.rend(), std::size_t(0));
                CHECK(bvh::lanes_walk_alone(rays, reversed, kIncoherentAloneMinBlocks) == !within);
                CHECK_FALSE(bvh::lanes_walk_alone(rays, reversed, kIncoherentAloneMinBlocks - 1));
            }
    });
}
