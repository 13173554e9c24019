// The builder: what every leaf references, the options, the guard, determinism, edge cases.
#include <doctest/doctest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "accel/octree/morton_order.h"
#include "accel/octree/octree.h"
#include "octree/octree_meshes.h"
#include "octree/octree_test_support.h"
#include "support/random_scenes.h"

using namespace trident;
using namespace trident::testing;

namespace {

/// Every triangle that meets a stored leaf's cell (by clipping, in double) is in that leaf, and
/// none meets the cell of an empty, unstored child. Also checks that indices stay in range.
void check_every_overlap_is_referenced(const Octree& tree) {
    const auto triangles = tree.triangles();
    std::size_t checked_leaves = 0;
    for_each_cell(tree, [&](std::optional<OctreeNode> node, const OctreeCube& cell, int depth) {
        CHECK(depth <= tree.max_depth());
        if (node && !node->is_leaf()) {
            CHECK(node->child_mask() != 0u);
            CHECK(node->first_child() + unsigned(std::popcount(node->child_mask())) <= tree.nodes().size());
            return;
        }
        std::vector<bool> listed(triangles.size(), false);
        if (node) {
            ++checked_leaves;
            REQUIRE(std::size_t(node->triangle_offset()) + node->triangle_count() <= tree.triangle_indices().size());
            for (std::uint32_t i = 0; i < node->triangle_count(); ++i) {
                const std::uint32_t position = tree.triangle_indices()[node->triangle_offset() + i];
                REQUIRE(position < triangles.size());
                listed[position] = true;
            }
        }
        const Vec3f hi = cell.lo + Vec3f(cell.size);
        for (std::size_t t = 0; t < triangles.size(); ++t) {
            if (listed[t]) continue;
            const Aabb box = triangles[t].bounds();
            if (box.lo.x > hi.x || box.lo.y > hi.y || box.lo.z > hi.z || box.hi.x < cell.lo.x || box.hi.y < cell.lo.y ||
                box.hi.z < cell.lo.z)
                continue;
            INFO("triangle ", tree.triangle_ids()[t], " meets a cell at depth ", depth,
                 node ? " but its leaf does not list it" : " that was left empty");
            CHECK_FALSE(triangle_meets_cell(triangles[t], cell));
        }
    });
    CHECK(checked_leaves == tree.stats().leaves);
}

void check_same_arrays(const Octree& a, const Octree& b) {
    CHECK(a.cube().lo == b.cube().lo);
    CHECK(a.cube().size == b.cube().size);
    CHECK(a.max_depth() == b.max_depth());
    CHECK(std::equal(a.nodes().begin(), a.nodes().end(), b.nodes().begin(), b.nodes().end()));
    CHECK(std::equal(a.triangle_indices().begin(), a.triangle_indices().end(), b.triangle_indices().begin(),
                     b.triangle_indices().end()));
    CHECK(
        std::equal(a.triangle_ids().begin(), a.triangle_ids().end(), b.triangle_ids().begin(), b.triangle_ids().end()));
    CHECK(a.stats().sah_cost == b.stats().sah_cost);
    CHECK(a.warning() == b.warning());
}

Octree build_with_one_thread(const Mesh& mesh, const OctreeOptions& options) {
    tbb::task_arena one(1);
    return one.execute([&] { return Octree::build(mesh, options); });
}

}  // namespace

TEST_CASE("every triangle is referenced by every leaf whose cell it overlaps, and empty children overlap none") {
    for (const OctreeOverlap overlap : {OctreeOverlap::triangle, OctreeOverlap::bounding_box}) {
        for (const float size : {0.05f, 0.3f}) {
            for (const int depth : {0, 3, 6}) {
                CAPTURE(int(overlap));
                CAPTURE(size);
                CAPTURE(depth);
                const Mesh mesh = random_soup(300, 17, size);
                const Octree tree = Octree::build(mesh, {.max_depth = depth, .overlap = overlap});
                CHECK(tree.warning().empty());
                check_every_overlap_is_referenced(tree);
            }
        }
    }
    check_every_overlap_is_referenced(Octree::build(flat_grid(24), {}));
    check_every_overlap_is_referenced(Octree::build(translated(random_soup(200, 3, 0.2f), {1e4f, -3e3f, 7e3f}), {}));
}

TEST_CASE("the separating-axis overlap holds no more references than the bounding-box overlap") {
    for (const float size : {0.05f, 0.2f, 0.6f}) {
        CAPTURE(size);
        const Mesh mesh = random_soup(2000, 5, size);
        const Octree sat = Octree::build(mesh, {.max_depth = 6});
        const Octree box = Octree::build(mesh, {.max_depth = 6, .overlap = OctreeOverlap::bounding_box});
        CHECK(sat.stats().references <= box.stats().references);
        if (size >= 0.2f) CHECK(sat.stats().references < box.stats().references);  // large triangles: a clear saving
    }
}

TEST_CASE("the built arrays are identical with one thread and with all threads") {
    const Mesh soup = random_soup(30000, 23, 0.05f);
    for (const OctreeOptions& options :
         {OctreeOptions{}, OctreeOptions{.max_depth = 7, .overlap = OctreeOverlap::bounding_box},
          OctreeOptions{.max_depth = 8, .max_references = 70000}}) {
        const Octree one = build_with_one_thread(soup, options);
        const Octree all = Octree::build(soup, options);
        check_same_arrays(one, all);
    }
}

TEST_CASE("the reference guard stops splitting, stays within its budget and says so") {
    const Mesh fan = fan_around(400, {0.1f, 0.2f, 0.3f}, 9);
    const OctreeOptions options{.max_depth = 12, .max_references = 20000};
    const Octree tree = Octree::build(fan, options);
    CHECK(tree.stats().references <= options.max_references);
    CHECK(tree.warning().find("reference guard") != std::string::npos);
    check_same_arrays(tree, build_with_one_thread(fan, options));
    check_every_overlap_is_referenced(tree);
    // The default guard is far above what ordinary scenes need.
    CHECK(Octree::build(random_soup(2000, 1, 0.1f), {.max_depth = 8}).warning().empty());
}

TEST_CASE("a flat scene (zero extent along z) builds a tree of the plane") {
    const Octree tree = Octree::build(flat_grid(32), {});
    CHECK(tree.cube().size > 0.9f);
    CHECK(tree.stats().max_depth >= 4);
    CHECK(tree.warning().empty());
    // Cells are cubes on the box's lower corner, so the plane is never on a centre plane and no
    // triangle is split between the z halves: only x and y children are stored.
    for_each_cell(tree, [&](std::optional<OctreeNode> node, const OctreeCube&, int) {
        if (node && !node->is_leaf()) CHECK((node->child_mask() & 0xF0u) == 0u);
    });
}

TEST_CASE("triangles collapsed into one point stop the split at once instead of blowing up") {
    const Mesh mesh = collapsed_to_point(1000, {0.25f, -3.0f, 7.0f});
    const Octree tree = Octree::build(mesh, {.max_depth = 12});
    CHECK(tree.stats().nodes <= 9);
    CHECK(tree.stats().references <= 8 * mesh.triangle_count());
    CHECK(tree.warning().empty());
    CHECK_FALSE(tree.intersect({{0.25f, -3.0f, 0.0f}, {0, 0, 1}}).is_hit());  // degenerate: nothing to hit
}

TEST_CASE("depth 1 is a root and at most 8 leaves") {
    const Octree tree = Octree::build(random_soup(500, 2), {.max_depth = 1});
    CHECK(tree.stats().nodes <= 9);
    CHECK(tree.stats().max_depth == 1);
    CHECK(!tree.nodes()[0].is_leaf());
}

TEST_CASE("an empty mesh and a single triangle build a root leaf") {
    const Octree empty = Octree::build(Mesh{}, {});
    CHECK(empty.stats().nodes == 1);
    CHECK(empty.stats().references == 0);
    CHECK(empty.stats().empty_leaves == 1);
    CHECK_FALSE(empty.intersect({{0, 0, -1}, {0, 0, 1}}).is_hit());
    CHECK_FALSE(empty.occluded({{0, 0, -1}, {0, 0, 1}}));

    Mesh one;
    one.add_triangle(one.add_vertex({0, 0, 0}), one.add_vertex({1, 0, 0}), one.add_vertex({0, 1, 0}));
    const Octree single = Octree::build(one, {});
    CHECK(single.stats().nodes == 1);
    CHECK(single.stats().references == 1);
    const Hit hit = single.intersect({{0.25f, 0.25f, 1}, {0, 0, -1}});
    CHECK(hit.triangle == 0u);
    CHECK(hit.t == doctest::Approx(1.0f));
}

TEST_CASE("with minimum primitives 0 every leaf sits at the maximum depth") {
    const Octree tree = Octree::build(random_soup(100, 4), {.max_depth = 4, .min_primitives = 0});
    for_each_cell(tree, [&](std::optional<OctreeNode> node, const OctreeCube&, int depth) {
        if (node && node->is_leaf()) CHECK(depth == 4);
    });
}

TEST_CASE("leaves above the maximum depth hold at most the minimum primitives") {
    for (const std::size_t min_primitives : {std::size_t(1), std::size_t(6)}) {
        CAPTURE(min_primitives);
        const Octree tree =
            Octree::build(random_soup(1000, 8, 0.05f), {.max_depth = 7, .min_primitives = min_primitives});
        std::size_t shallow_leaves = 0;
        for_each_cell(tree, [&](std::optional<OctreeNode> node, const OctreeCube&, int depth) {
            if (!node || !node->is_leaf() || depth == 7) return;
            ++shallow_leaves;
            CHECK(node->triangle_count() <= min_primitives);
        });
        CHECK(shallow_leaves > 100);
    }
}

TEST_CASE("options out of range are rejected with a message") {
    const Mesh mesh = random_soup(10, 1);
    CHECK_THROWS_AS(Octree::build(mesh, {.max_depth = 13}), std::invalid_argument);
    CHECK_THROWS_AS(Octree::build(mesh, {.max_depth = -1}), std::invalid_argument);
    CHECK_THROWS_WITH(validate(OctreeOptions{.max_depth = 20}), doctest::Contains("between 1 and 12"));
    CHECK_NOTHROW(Octree::build(mesh, {.max_depth = 12}));
}

TEST_CASE("triangles with non-finite corners are left out and reported") {
    Mesh mesh = random_soup(50, 6);
    const auto a = mesh.add_vertex({std::nanf(""), 0, 0});
    mesh.add_triangle(a, 0, 1);
    const Octree tree = Octree::build(mesh, {});
    CHECK(tree.triangles().size() == 50);
    CHECK(tree.warning().find("non-finite") != std::string::npos);
    check_every_overlap_is_referenced(tree);
}

TEST_CASE("the default depth is the shallowest whose occupied cells hold 10 triangles or fewer") {
    // A grid of n x n squares (2 n^2 triangles) filling a square face of the cube: a cell at depth
    // d covers (n / 2^d)^2 squares, so the depth is the first with 2 n^2 / 4^d <= 10.
    auto depth_of = [](const Mesh& mesh) { return Octree::build(mesh, {}).max_depth(); };
    CHECK(depth_of(flat_grid(16)) == 3);
    CHECK(depth_of(flat_grid(64)) == 5);
    CHECK(depth_of(flat_grid(64, 1000.0f)) == 5);  // the scale does not matter
    CHECK(depth_of(flat_grid(128)) == 6);
    CHECK(depth_of(Mesh{}) == 1);
    CHECK(depth_of(collapsed_to_point(10, {1, 2, 3})) == 1);
    // Never fewer than 11 a cell would ask for the deepest default, 9, but the cube around a point
    // is a hair wide: cells that deep would be smaller than the coordinates' rounding.
    CHECK(depth_of(collapsed_to_point(11, {1, 2, 3})) == 1);
}

TEST_CASE("far from the origin the default depth stops where cells near the coordinates' rounding") {
    auto depth_of = [](const Mesh& mesh) { return Octree::build(mesh, {}).max_depth(); };
    Mesh far = flat_grid(64);
    const int near_depth = depth_of(far);
    for (std::size_t i = 0; i < far.vertex_count(); ++i) far.x[i] += 1e6f;
    const Octree tree = Octree::build(far, {});
    CHECK(tree.max_depth() < near_depth);
    CHECK(tree.max_depth() >= 1);
    check_every_overlap_is_referenced(tree);
}

TEST_CASE("occupied cells are counted per depth from sorted Morton keys") {
    const OctreeCube cube{{0, 0, 0}, 1.0f};
    // Two points in the lowest and highest child, one more beside the first at depth 3.
    std::vector<std::uint32_t> keys{morton_key({0.01f, 0.01f, 0.01f}, cube), morton_key({0.2f, 0.01f, 0.01f}, cube),
                                    morton_key({0.99f, 0.99f, 0.99f}, cube), morton_key({0.99f, 0.99f, 0.99f}, cube)};
    std::sort(keys.begin(), keys.end());
    const std::vector<std::size_t> occupied = occupied_cells_per_depth(keys);
    REQUIRE(occupied.size() == std::size_t(kMortonBitsPerAxis) + 1);
    CHECK(occupied[0] == 1);
    CHECK(occupied[1] == 2);
    CHECK(occupied[2] == 2);
    CHECK(occupied[3] == 3);                                       // 0.2 and 0.01 part at 1/8
    CHECK(occupied[10] == 3);                                      // the two equal points never part
    CHECK((morton_key({0.99f, 0.01f, 0.01f}, cube) >> 27) == 1u);  // child 1 = upper x
    CHECK((morton_key({0.01f, 0.01f, 0.99f}, cube) >> 27) == 4u);  // child 4 = upper z
}

TEST_CASE("node layout: 8 bytes, child slots skip the empty children") {
    const OctreeNode node = OctreeNode::interior(10, 0b10100101u);
    CHECK_FALSE(node.is_leaf());
    CHECK(node.child_slot(0) == 10u);
    CHECK(node.child_slot(2) == 11u);
    CHECK(node.child_slot(5) == 12u);
    CHECK(node.child_slot(7) == 13u);
    CHECK_FALSE(node.has_child(1));
    const OctreeNode leaf = OctreeNode::leaf(123456, OctreeNode::kMaxLeafCount);
    CHECK(leaf.is_leaf());
    CHECK(leaf.triangle_offset() == 123456u);
    CHECK(leaf.triangle_count() == OctreeNode::kMaxLeafCount);
}

TEST_CASE("statistics describe the arrays") {
    const Octree tree = Octree::build(random_soup(3000, 12, 0.1f), {.max_depth = 6});
    const AccelStats& s = tree.stats();
    std::size_t leaves = 0, empty_children = 0, deepest = 0, largest = 0;
    for_each_cell(tree, [&](std::optional<OctreeNode> node, const OctreeCube&, int depth) {
        if (!node) {
            ++empty_children;
        } else if (node->is_leaf()) {
            ++leaves;
            deepest = std::max(deepest, std::size_t(depth));
            largest = std::max<std::size_t>(largest, node->triangle_count());
        }
    });
    CHECK(s.structure == "octree");
    CHECK(s.triangles == 3000);
    CHECK(s.nodes == tree.nodes().size());
    CHECK(s.leaves == leaves);
    CHECK(s.empty_leaves == empty_children);
    CHECK(s.max_depth == deepest);
    CHECK(s.max_leaf_size == largest);
    CHECK(s.references == tree.triangle_indices().size());
    CHECK(s.mean_leaf_size == doctest::Approx(double(s.references) / double(leaves)));
    CHECK(s.sah_cost > 0.0);
    CHECK(s.sah_cost < double(s.references));  // weights below 1 for every node but the root
    CHECK(s.bytes == tree.nodes().size() * 8 + tree.triangle_indices().size() * 4 + 3000 * (36 + 4));
    CHECK(s.build_ms > 0.0);
    CHECK(!s.to_line().empty());
}
