// What the kd-tree builder promises about the tree it makes: every triangle in every leaf whose
// cell it overlaps, perfect splits dropping the cells a triangle misses, limits honoured, edge
// cases, statistics, and the same tree whatever the thread count.
#include <doctest/doctest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <utility>
#include <vector>

#include "accel/kdtree/kdtree.h"
#include "core/triangle_box_overlap.h"
#include "kdtree/kd_test_support.h"
#include "support/random_scenes.h"

using namespace trident;
using namespace trident::testing;

namespace {

/// Does the triangle meet the box centred at `centre` with half-extents `half`? In double, by
/// separating axes; touching counts.
bool overlaps(const Triangle& tri, const Vec3d& centre, const Vec3d& half) {
    return triangle_overlaps_box(Vec3d(tri.a), Vec3d(tri.b), Vec3d(tri.c), centre, half);
}

/// Does the triangle meet the cell shrunk by `margin` on every side, that is, overlap it beyond
/// touching? Axes on which the whole scene is flat are not shrunk; a cell flat on another axis
/// has no inside.
bool overlaps_inside(const Triangle& tri, const Aabb& cell, const Aabb& root, double margin) {
    const Vec3d lo(cell.lo), hi(cell.hi);
    Vec3d half = (hi - lo) * 0.5;
    for (int axis = 0; axis < 3; ++axis) {
        if (root.lo[axis] == root.hi[axis]) continue;
        half[axis] -= margin;
        if (half[axis] < 0.0) return false;
    }
    return overlaps(tri, (lo + hi) * 0.5, half);
}

/// Does the triangle meet the cell grown by `margin` on every side?
bool overlaps_grown(const Triangle& tri, const Aabb& cell, double margin) {
    const Vec3d lo(cell.lo), hi(cell.hi);
    return overlaps(tri, (lo + hi) * 0.5, (hi - lo) * 0.5 + Vec3d(margin));
}

/// The leaf's run as stored: indices into tree.triangles().
std::span<const TriangleId> leaf_indices(const KdTree& tree, const KdNode& leaf) {
    return tree.leaf_triangles().subspan(leaf.triangle_offset(), leaf.triangle_count());
}

/// The leaf's triangles as file indices, ascending.
std::vector<TriangleId> leaf_run(const KdTree& tree, const KdNode& leaf) {
    std::vector<TriangleId> run;
    for (const TriangleId index : leaf_indices(tree, leaf)) run.push_back(tree.triangle_ids()[index]);
    std::sort(run.begin(), run.end());
    return run;
}

/// The structural promises of the layout: children and runs in range, every node reached once,
/// runs ascending, depth within the limit, each interior node's marks of empty children true.
void check_layout(const KdTree& tree, std::size_t triangle_count, int depth_limit) {
    const auto nodes = tree.nodes();
    std::vector<int> reached(nodes.size(), 0);
    for (const KdCell& c : kd_cells(tree)) {
        REQUIRE(c.node < nodes.size());
        ++reached[c.node];
        CHECK(c.depth <= depth_limit);
        const KdNode& node = nodes[c.node];
        if (node.is_leaf()) {
            REQUIRE(std::size_t(node.triangle_offset()) + node.triangle_count() <= tree.leaf_triangles().size());
            const std::span<const TriangleId> run = leaf_indices(tree, node);
            CHECK(std::is_sorted(run.begin(), run.end()));
            CHECK(std::adjacent_find(run.begin(), run.end()) == run.end());
            for (const TriangleId index : run) CHECK(index < tree.triangles().size());
            for (const TriangleId id : leaf_run(tree, node)) CHECK(id < triangle_count);
        } else {
            REQUIRE(node.above_child() < nodes.size());
            CHECK(node.below_empty() == nodes[node.below_child()].is_empty_leaf());
            CHECK(node.above_empty() == nodes[node.above_child()].is_empty_leaf());
            CHECK(node.split() >= c.cell.lo[node.axis()]);
            CHECK(node.split() <= c.cell.hi[node.axis()]);
        }
    }
    CHECK(std::all_of(reached.begin(), reached.end(), [](int r) { return r == 1; }));
}

/// The leaves whose closed cells contain p (both sides where p lies on a split plane).
std::vector<std::uint32_t> leaves_containing(const KdTree& tree, const Vec3f& p) {
    std::vector<std::uint32_t> out, pending{0};
    while (!pending.empty()) {
        const std::uint32_t index = pending.back();
        pending.pop_back();
        const KdNode& node = tree.nodes()[index];
        if (node.is_leaf()) {
            out.push_back(index);
            continue;
        }
        if (p[node.axis()] <= node.split()) pending.push_back(node.below_child());
        if (p[node.axis()] >= node.split()) pending.push_back(node.above_child());
    }
    return out;
}

/// Each triangle is in every leaf whose cell it overlaps by more than `margin`, and every point of
/// it (sampled) lies in the cell of some leaf that holds it, which covers triangles lying in split
/// planes too. With perfect splits, no leaf holds a triangle missing its cell by more than
/// `margin`. Returns how many (triangle, leaf) overlaps beyond touching were checked.
std::size_t check_references(const KdTree& tree, const Mesh& mesh, bool perfect, double margin) {
    const std::vector<Triangle> triangles = gather_triangles(mesh);
    std::size_t overlapping = 0;
    for (const KdCell& c : kd_cells(tree)) {
        const KdNode& leaf = tree.nodes()[c.node];
        if (!leaf.is_leaf()) continue;
        const std::vector<TriangleId> run = leaf_run(tree, leaf);
        const std::set<TriangleId> held(run.begin(), run.end());
        for (TriangleId id = 0; id < triangles.size(); ++id) {
            if (overlaps_inside(triangles[id], c.cell, tree.bounds(), margin)) {
                INFO("triangle ", id, " overlaps the cell of leaf ", c.node);
                CHECK(held.count(id) == 1);
                ++overlapping;
            }
        }
        if (perfect)
            for (const TriangleId id : run) {
                INFO("triangle ", id, " is held by leaf ", c.node);
                CHECK(overlaps_grown(triangles[id], c.cell, margin));
            }
    }
    // Weights whose float sums are exact: a point of a triangle lying in a plane stays in it.
    const float weights[][3] = {{1, 0, 0},
                                {0, 1, 0},
                                {0, 0, 1},
                                {0.5f, 0.5f, 0},
                                {0, 0.5f, 0.5f},
                                {0.5f, 0, 0.5f},
                                {0.25f, 0.25f, 0.5f},
                                {0.5f, 0.25f, 0.25f}};
    for (TriangleId id = 0; id < triangles.size(); ++id) {
        const Triangle& t = triangles[id];
        for (const auto& w : weights) {
            const Vec3f p = t.a * w[0] + t.b * w[1] + t.c * w[2];
            bool covered = false;
            for (const std::uint32_t index : leaves_containing(tree, p)) {
                const std::vector<TriangleId> run = leaf_run(tree, tree.nodes()[index]);
                covered = covered || std::binary_search(run.begin(), run.end(), id);
            }
            INFO("triangle ", id, " at (", p.x, ", ", p.y, ", ", p.z, ")");
            CHECK(covered);
        }
    }
    return overlapping;
}

KdTreeOptions with_perfect_splits(bool perfect) {
    KdTreeOptions options;
    options.perfect_splits = perfect;
    return options;
}

/// Calls f(mesh, options) for a soup of `soup_triangles` and a grid of flat boxes (planar triangles
/// on shared planes), each without and with perfect splits.
template <class F>
void for_each_mesh_and_split_mode(std::size_t soup_triangles, F f) {
    const Mesh soup = random_soup(soup_triangles, 4, 0.1f);
    const Mesh boxes = grid_boxes(300, 6, 24);
    for (const Mesh* mesh : {&soup, &boxes})
        for (const bool perfect : {false, true}) {
            CAPTURE(perfect);
            f(*mesh, with_perfect_splits(perfect));
        }
}

void check_same_tree(const KdTree& a, const KdTree& b) {
    CHECK(std::ranges::equal(a.nodes(), b.nodes()));
    CHECK(std::ranges::equal(a.leaf_triangles(), b.leaf_triangles()));
}

}  // namespace

TEST_CASE("every triangle is referenced by every leaf whose cell it overlaps") {
    for (const bool perfect : {false, true}) {
        CAPTURE(perfect);
        for (const float size : {0.05f, 0.4f}) {
            CAPTURE(size);
            const Mesh mesh = random_soup(300, 21, size);
            const KdTree tree = KdTree::build(mesh, with_perfect_splits(perfect));
            check_layout(tree, mesh.triangle_count(), KdTreeOptions{}.depth_limit(mesh.triangle_count()));
            CHECK(check_references(tree, mesh, perfect, 1e-5) >= mesh.triangle_count());
        }
        const Mesh boxes = grid_boxes(40, 5);
        const KdTree tree = KdTree::build(boxes, with_perfect_splits(perfect));
        check_layout(tree, boxes.triangle_count(), KdTreeOptions{}.depth_limit(boxes.triangle_count()));
        check_references(tree, boxes, perfect, 1e-5);
    }
}

TEST_CASE("children that are leaves at once (size or depth) get no event lists, and the tree stays whole") {
    // The builder skips the event lists of a child with at most leaf_triangles triangles or at the
    // depth limit; its siblings' lists must still come out complete and sorted.
    const Mesh mesh = random_soup(500, 33, 0.2f);
    for (const bool perfect : {false, true}) {
        for (const std::size_t leaf_triangles : {std::size_t(1), std::size_t(3), std::size_t(8)}) {
            for (const int max_depth : {3, 7, -1}) {
                CAPTURE(perfect);
                CAPTURE(leaf_triangles);
                CAPTURE(max_depth);
                KdTreeOptions options = with_perfect_splits(perfect);
                options.leaf_triangles = leaf_triangles;
                options.max_depth = max_depth;
                const KdTree tree = KdTree::build(mesh, options);
                check_layout(tree, mesh.triangle_count(), options.depth_limit(mesh.triangle_count()));
                check_references(tree, mesh, perfect, 1e-5);
            }
        }
    }
}

TEST_CASE("perfect splits lower the SAH cost of a soup of large triangles") {
    // Large triangles straddle many planes; clipping drops them from cells they miss although
    // their bounding boxes overlap them.
    const Mesh mesh = random_soup(400, 8, 0.5f);
    const KdTree clamped = KdTree::build(mesh, with_perfect_splits(false));
    const KdTree perfect = KdTree::build(mesh, with_perfect_splits(true));
    CHECK(perfect.stats().sah_cost < clamped.stats().sah_cost);
}

TEST_CASE("the tree is the same for one thread, all threads and any task size") {
    for_each_mesh_and_split_mode(6000, [](const Mesh& mesh, KdTreeOptions options) {
        options.parallel_triangles = 64;
        const KdTree all_threads = KdTree::build(mesh, options);
        KdTree one_thread;
        tbb::task_arena(1).execute([&] { one_thread = KdTree::build(mesh, options); });
        options.parallel_triangles = std::numeric_limits<std::size_t>::max();
        const KdTree sequential = KdTree::build(mesh, options);
        for (const KdTree* other : {&std::as_const(one_thread), &sequential}) check_same_tree(all_threads, *other);
        CHECK(all_threads.nodes().size() > 100);
    });
}

TEST_CASE("small nodes built from their box ends give the tree the event lists give") {
    for_each_mesh_and_split_mode(3000, [](const Mesh& mesh, KdTreeOptions options) {
        options.small_node_triangles = 0;
        const KdTree from_events = KdTree::build(mesh, options);
        for (const std::size_t small : {std::size_t(3), KdTreeOptions::kMaxSmallNodeTriangles}) {
            CAPTURE(small);
            options.small_node_triangles = small;
            check_same_tree(from_events, KdTree::build(mesh, options));
        }
        CHECK(from_events.nodes().size() > 1000);
    });
}

TEST_CASE("an empty mesh builds an empty tree that every ray misses") {
    const KdTree tree = KdTree::build(Mesh{});
    CHECK(tree.nodes().empty());
    CHECK(tree.stats().nodes == 0);
    CHECK(tree.stats().references == 0);
    const Ray ray{{0, 0, -1}, {0, 0, 1}};
    CHECK_FALSE(tree.intersect(ray).is_hit());
    CHECK(tree.intersect(ray).t == kInfinity);
    CHECK_FALSE(tree.occluded(ray));
}

TEST_CASE("one triangle is one leaf") {
    Mesh mesh;
    mesh.add_triangle(mesh.add_vertex({0, 0, 0}), mesh.add_vertex({1, 0, 0}), mesh.add_vertex({0, 1, 0}));
    const KdTree tree = KdTree::build(mesh);
    REQUIRE(tree.nodes().size() == 1);
    CHECK(tree.nodes()[0].is_leaf());
    CHECK(tree.stats().leaves == 1);
    const Hit hit = tree.intersect(Ray{{0.25f, 0.25f, 1.0f}, {0, 0, -1}});
    CHECK(hit.triangle == 0);
    CHECK(hit.t == 1.0f);
    CHECK_FALSE(tree.intersect(Ray{{0.75f, 0.75f, 1.0f}, {0, 0, -1}}).is_hit());
}

TEST_CASE("many identical triangles stop at the bad-refinement limit with a small tree") {
    Mesh mesh;
    for (int i = 0; i < 2000; ++i)
        mesh.add_triangle(mesh.add_vertex({0.1f, 0.2f, 0.3f}), mesh.add_vertex({0.9f, 0.4f, 0.5f}),
                          mesh.add_vertex({0.3f, 0.8f, 0.1f}));
    for (const bool perfect : {false, true}) {
        CAPTURE(perfect);
        const KdTree tree = KdTree::build(mesh, with_perfect_splits(perfect));
        CHECK(tree.stats().nodes < 200);
        CHECK(tree.stats().max_depth < 12);
        const Hit hit = tree.intersect(Ray{{0.4f, 0.45f, 5.0f}, {0, 0, -1}});
        CHECK(hit.is_hit());
        CHECK(hit.triangle == 0);  // ties between duplicates go to the lowest index
    }
}

TEST_CASE("the depth limit holds, and a limit of zero gives one leaf") {
    const Mesh mesh = random_soup(2000, 12, 0.05f);
    KdTreeOptions options;
    options.max_depth = 5;
    CHECK(KdTree::build(mesh, options).stats().max_depth == 5);
    options.max_depth = 0;
    const KdTree flat = KdTree::build(mesh, options);
    CHECK(flat.nodes().size() == 1);
    CHECK(flat.stats().references == mesh.triangle_count());
    CHECK(KdTreeOptions{}.depth_limit(1 << 20) == 34);  // round(8 + 1.3 * 20)
    CHECK(KdTreeOptions{}.depth_limit(0) == 8);
}

TEST_CASE("a depth offset moves pbrt's limit, within 0..kKdMaxDepth - 1, and an explicit limit ignores it") {
    auto offset_by = [](int levels) {
        KdTreeOptions options;
        options.depth_offset = levels;
        return options;
    };
    CHECK(offset_by(6).depth_limit(1 << 20) == 40);
    CHECK(offset_by(-4).depth_limit(1 << 20) == 30);
    CHECK(offset_by(-20).depth_limit(0) == 0);
    CHECK(offset_by(kKdMaxDepth - 1).depth_limit(1 << 20) == kKdMaxDepth - 1);
    KdTreeOptions explicit_limit = offset_by(6);
    explicit_limit.max_depth = 5;
    CHECK(explicit_limit.depth_limit(1 << 20) == 5);

    // A soup dense enough that pbrt's limit stops it (round(8 + 1.3 log2 4000) = 24): two levels
    // fewer give a shallower tree, two more a deeper one.
    const Mesh mesh = random_soup(4000, 13, 0.2f);
    const int pbrt_depth = KdTree::build(mesh).stats().max_depth;
    REQUIRE(pbrt_depth == KdTreeOptions{}.depth_limit(mesh.triangle_count()));
    CHECK(KdTree::build(mesh, offset_by(-2)).stats().max_depth == pbrt_depth - 2);
    CHECK(KdTree::build(mesh, offset_by(2)).stats().max_depth > pbrt_depth);
}

TEST_CASE("triangles with a non-finite corner are left out of the tree") {
    Mesh mesh = random_soup(50, 2, 0.2f);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    mesh.add_triangle(mesh.add_vertex({nan, 0, 0}), mesh.add_vertex({1, 0, 0}), mesh.add_vertex({0, 1, 0}));
    mesh.add_triangle(mesh.add_vertex({0, kInfinity, 0}), mesh.add_vertex({1, 0, 0}), mesh.add_vertex({0, 1, 0}));
    const KdTree tree = KdTree::build(mesh);
    CHECK(tree.bounds().hi.x <= 2.0f);
    for (const TriangleId index : tree.leaf_triangles()) CHECK(tree.triangle_ids()[index] < 50);
    CHECK(tree.triangles().size() == 50);
    CHECK(tree.triangle_ids().size() == 50);
}

TEST_CASE("the tree holds each finite triangle once, reordered, with its file index") {
    Mesh mesh = random_soup(400, 23, 0.1f);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    mesh.add_triangle(mesh.add_vertex({nan, 0, 0}), mesh.add_vertex({1, 0, 0}), mesh.add_vertex({0, 1, 0}));
    const KdTree tree = KdTree::build(mesh);
    const std::vector<Triangle> file_order = gather_triangles(mesh);
    REQUIRE(tree.triangles().size() == 400);
    REQUIRE(tree.triangle_ids().size() == 400);
    std::vector<TriangleId> ids(tree.triangle_ids().begin(), tree.triangle_ids().end());
    for (std::size_t i = 0; i < ids.size(); ++i) {
        const Triangle& held = tree.triangles()[i];
        const Triangle& original = file_order[ids[i]];
        CHECK((held.a == original.a && held.b == original.b && held.c == original.c));
    }
    std::sort(ids.begin(), ids.end());
    for (TriangleId id = 0; id < 400; ++id) CHECK(ids[id] == id);                    // a permutation of the finite ones
    CHECK(!std::is_sorted(tree.triangle_ids().begin(), tree.triangle_ids().end()));  // random soup: reordered
}

TEST_CASE("statistics describe the tree") {
    const Mesh mesh = random_soup(3000, 17, 0.1f);
    const KdTree tree = KdTree::build(mesh);
    const AccelStats& s = tree.stats();
    CHECK(s.structure == "kdtree");
    CHECK(s.triangles == 3000);
    CHECK(s.nodes == tree.nodes().size());
    CHECK(s.nodes == 2 * s.leaves - 1);
    CHECK(s.references == tree.leaf_triangles().size());
    CHECK(s.references >= s.triangles);
    CHECK(s.empty_leaves > 0);
    CHECK(s.empty_leaves < s.leaves);
    std::size_t leaves = 0, empty = 0, largest = 0;
    for (const KdNode& n : tree.nodes())
        if (n.is_leaf()) {
            ++leaves;
            empty += n.triangle_count() == 0;
            largest = std::max<std::size_t>(largest, n.triangle_count());
        }
    CHECK(s.leaves == leaves);
    CHECK(s.empty_leaves == empty);
    CHECK(s.max_leaf_size == largest);
    CHECK(s.mean_leaf_size == doctest::Approx(double(s.references) / double(leaves - empty)));
    CHECK(s.bytes == s.nodes * 8 + s.references * 4 + 3000 * (sizeof(Triangle) + sizeof(TriangleId)));
    // The SAH cost lies between a tree's floor (one traversal step, then at least one triangle
    // test for every ray that hits something) and a single leaf's (every triangle, 80 each).
    CHECK(s.sah_cost > 1.0);
    CHECK(s.sah_cost < 80.0 * 3000);
    CHECK(s.build_ms >= 0.0);
    CHECK(s.to_line().find("kdtree") == 0);
}

TEST_CASE("options out of range are refused, naming the field") {
    auto refused = [](auto change) {
        KdTreeOptions options;
        change(options);
        return options;
    };
    const Mesh mesh = random_soup(10, 1);
    CHECK_THROWS_WITH_AS(KdTree::build(mesh, refused([](KdTreeOptions& o) { o.intersection_cost = 0; })),
                         doctest::Contains("intersection_cost"), std::invalid_argument);
    CHECK_THROWS_WITH_AS(KdTree::build(mesh, refused([](KdTreeOptions& o) { o.empty_bonus = 1; })),
                         doctest::Contains("empty_bonus"), std::invalid_argument);
    CHECK_THROWS_WITH_AS(KdTree::build(mesh, refused([](KdTreeOptions& o) { o.max_depth = kKdMaxDepth; })),
                         doctest::Contains("max_depth"), std::invalid_argument);
    CHECK_THROWS_WITH_AS(KdTree::build(mesh, refused([](KdTreeOptions& o) { o.depth_offset = -kKdMaxDepth; })),
                         doctest::Contains("depth_offset"), std::invalid_argument);
    CHECK_THROWS_WITH_AS(KdTree::build(mesh, refused([](KdTreeOptions& o) { o.leaf_triangles = 0; })),
                         doctest::Contains("leaf_triangles"), std::invalid_argument);
    CHECK_THROWS_WITH_AS(KdTree::build(mesh, refused([](KdTreeOptions& o) { o.max_bad_refines = 0; })),
                         doctest::Contains("max_bad_refines"), std::invalid_argument);
    CHECK_THROWS_WITH_AS(KdTree::build(mesh, refused([](KdTreeOptions& o) {
                                           o.small_node_triangles = KdTreeOptions::kMaxSmallNodeTriangles + 1;
                                       })),
                         doctest::Contains("small_node_triangles"), std::invalid_argument);
}

TEST_CASE("a flat scene builds a real tree") {
    // Every triangle lies in z = 0: all z events are planar, the z axis offers no split, x and y do.
    Mesh mesh = random_soup(500, 9, 0.05f);
    for (float& z : mesh.z) z = 0.0f;
    const KdTree tree = KdTree::build(mesh);
    CHECK(tree.bounds().lo.z == 0.0f);
    CHECK(tree.bounds().hi.z == 0.0f);
    CHECK(tree.stats().leaves > 50);
    for (const SplitPlane& plane : kd_split_planes(tree)) CHECK(plane.axis != 2);
    CHECK(check_references(tree, mesh, false, 1e-5) >= mesh.triangle_count());
}
