// The flattened layout's invariants, the statistics, determinism across thread counts, and the
// traversal counters.
#include <doctest/doctest.h>
#include <tbb/task_arena.h>

#include <cstring>
#include <stdexcept>
#include <type_traits>

#include "accel/bvh/build_primitives.h"
#include "accel/bvh/tree_builder.h"
#include "bvh_test_helpers.h"
#include "support/random_scenes.h"
#include "support/sanitizer_workload.h"

using namespace trident;
using namespace trident::testing;
using namespace trident::bvh;

TEST_CASE("the flattened tree keeps every invariant on random soups, for every builder setting") {
    BvhOptions sweep;
    sweep.builder = BvhBuilder::sweep_sah;
    BvhOptions one_per_leaf;
    one_per_leaf.max_leaf_size = 1;
    BvhOptions big_leaves;
    big_leaves.max_leaf_size = 255;
    big_leaves.intersection_cost = 0.01f;  // leaves become cheap: SAH keeps them large
    BvhOptions sixty_four;
    sixty_four.bin_count = 64;
    sixty_four.large_node_bin_count = 64;
    BvhOptions spatial;
    spatial.builder = BvhBuilder::spatial_sah;
    for (const BvhOptions& options :
         {BvhOptions{}, BvhOptions::study(), sweep, one_per_leaf, big_leaves, sixty_four, spatial})
        for (std::size_t count : {1u, 2u, 3u, 50u, 5000u}) {
            CAPTURE(count);
            CAPTURE(to_string(options.builder));
            CAPTURE(options.max_leaf_size);
            const Mesh mesh = random_soup(count, std::uint32_t(count), 0.1f);
            check_invariants(Bvh::build(mesh, options), mesh);
        }
}

TEST_CASE("large leaves are allowed when SAH wants them and capped by max_leaf_size") {
    const Mesh mesh = random_soup(2000, 4, 0.1f);
    BvhOptions options;
    options.intersection_cost = 0.001f;
    options.max_leaf_size = 32;
    const Bvh bvh = Bvh::build(mesh, options);
    check_invariants(bvh, mesh);
    CHECK(bvh.stats().max_leaf_size > 8);
    CHECK(bvh.stats().max_leaf_size <= 32);
}

TEST_CASE("for the wide BVH, a node of one block is split only where its children's boxes are far smaller") {
    // Two unit quads (two triangles each, in z = 0) side by side, `gap` apart along x.
    const auto two_quads = [](float gap) {
        Mesh mesh;
        for (const float x : {0.0f, 1.0f + gap}) {
            const auto a = mesh.add_vertex({x, 0, 0}), b = mesh.add_vertex({x + 1, 0, 0});
            const auto c = mesh.add_vertex({x + 1, 1, 0}), d = mesh.add_vertex({x, 1, 0});
            mesh.add_triangle(a, b, c);
            mesh.add_triangle(a, c, d);
        }
        return mesh;
    };
    const Mesh touching = two_quads(0.0f), apart = two_quads(100.0f);
    BvhOptions spatial;
    spatial.builder = BvhBuilder::spatial_sah;
    for (BvhOptions options : {BvhOptions{}, spatial}) {
        CAPTURE(to_string(options.builder));
        // The binary tree's SAH splits the 2x1 strip: a node step and two tests a side (4 + 2 * 2 + 2 * 2)
        // cost less than four tests over the whole strip (4 * 4).
        const Bvh binary = Bvh::build(touching, options);
        check_invariants(binary, touching);
        CHECK(binary.nodes().size() > 1);
        // Blocks of four: the quads' boxes add up to the strip's (2 + 2 against 4), so a block test over
        // each quad costs as much as one over the strip, and the split would take a slot more: a leaf.
        options.leaf_block_size = 4;
        const Bvh strip = Bvh::build(touching, options);
        check_invariants(strip, touching);
        CHECK(strip.nodes().size() == 1);
        // 100 apart, the quads' boxes are a sliver of the node's (4 against 204): split into one leaf a
        // quad, whose two triangles share one box and stay together.
        const Bvh split = Bvh::build(apart, options);
        check_invariants(split, apart);
        REQUIRE(split.nodes().size() == 3);
        CHECK(split.nodes()[1].triangle_count() == 2);
        CHECK(split.nodes()[2].triangle_count() == 2);
    }
    BvhOptions bad;
    for (const int size : {0, bad.max_leaf_size + 1}) {
        bad.leaf_block_size = size;
        CHECK_THROWS_AS(bad.validate(), std::invalid_argument);
    }
}

TEST_CASE("the flattened tree keeps every invariant on the built-in scenes") {
    for (const std::string& name : builtin_scene_names_under_test()) {
        CAPTURE(name);
        check_invariants(builtin_bvh(name), builtin_scene(name).mesh);
    }
}

TEST_CASE("one thread and all threads build the same flattened tree, byte for byte") {
    // Large enough for parallel binning, parallel subtrees and the large-node bins.
    BvhOptions sweep;
    sweep.builder = BvhBuilder::sweep_sah;
    BvhOptions spatial;
    spatial.builder = BvhBuilder::spatial_sah;
    for (const BvhOptions& options : {BvhOptions{}, BvhOptions::study(), sweep, spatial}) {
        CAPTURE(to_string(options.builder));
        const Mesh mesh = random_soup(options.builder == BvhBuilder::binned_sah ? 70000 : 30000, 9, 0.02f);
        tbb::task_arena one_thread(1);
        Bvh serial = one_thread.execute([&] { return Bvh::build(mesh, options); });
        Bvh parallel = Bvh::build(mesh, options);
        REQUIRE(serial.nodes().size() == parallel.nodes().size());
        CHECK(std::memcmp(serial.nodes().data(), parallel.nodes().data(), serial.nodes().size_bytes()) == 0);
        CHECK(std::memcmp(serial.leaf_triangle_ids().data(), parallel.leaf_triangle_ids().data(),
                          serial.leaf_triangle_ids().size_bytes()) == 0);
        CHECK(std::memcmp(serial.leaf_triangles().data(), parallel.leaf_triangles().data(),
                          serial.leaf_triangles().size_bytes()) == 0);
    }
}

namespace {

/// A splitter whose SAH always wants to cut off a single triangle: left alone, the tree would be
/// as deep as there are triangles.
struct PeelOneSplitter {
    struct Split {
        float cost = 0.0f;
    };
    HugePageArray<PrimitiveRef>& refs;

    Split find_sah_split(const BuildRange&) const { return {}; }
    ChildRanges partition(const BuildRange& range, const Split&) { return split_at(range, range.begin + 1); }
    ChildRanges partition_median(const BuildRange& range) { return split_at(range, range.begin + range.count() / 2); }

    ChildRanges split_at(const BuildRange& range, std::uint32_t mid) const {
        ChildRanges out{{range.begin, mid, {}, {}}, {mid, range.end, {}, {}}, 0};
        for (BuildRange* side : {&out.left, &out.right})
            for (std::uint32_t i = side->begin; i != side->end; ++i) {
                side->bounds.extend(refs[i].bounds());
                side->centroid_bounds.extend(refs[i].centroid());
            }
        return out;
    }
};

}  // namespace

TEST_CASE("the tree never gets deeper than the traversal stack, even when SAH peels one triangle at a time") {
    for (std::size_t count : {40u, 1000u, 20000u}) {
        CAPTURE(count);
        const Mesh mesh = random_soup(count, 3, 0.1f);
        HugePageArray<PrimitiveRef> refs = make_primitive_refs(mesh);
        PeelOneSplitter splitter{refs};
        BvhOptions options;
        options.max_leaf_size = 1;
        const HugePageArray<BvhNode> nodes = TreeBuilder(splitter, options).build(whole_range(refs));
        const AccelStats stats = bvh_stats(nodes, count, options);
        CHECK(stats.leaves == count);
        CHECK(stats.references == count);
        CHECK(stats.max_depth == std::min<std::size_t>(count - 1, kBvhMaxDepth));
    }
}

TEST_CASE("traversal counters count box tests and triangle tests; NoCounters costs nothing") {
    static_assert(std::is_empty_v<NoCounters>);
    const Mesh mesh = random_soup(4000, 21, 0.05f);
    const Bvh bvh = Bvh::build(mesh);
    const Aabb box = mesh.bounds();

    // A ray that hits the root box visits at least the root; one that misses it visits only the root.
    TraversalCounters missing;
    const Ray away{box.hi + Vec3f{1.0f}, {1.0f, 1.0f, 1.0f}};
    CHECK_FALSE(bvh.intersect<TriangleTest::watertight>(away, missing).is_hit());
    CHECK(missing.nodes_visited == 1);
    CHECK(missing.triangles_tested == 0);

    TraversalCounters total;
    std::size_t hits = 0;
    const std::vector<Ray> rays = random_rays(box, 500, 22, 0);
    for (const Ray& ray : rays) {
        TraversalCounters counters;
        NoCounters none;
        const Hit counted = bvh.intersect<TriangleTest::watertight>(ray, counters);
        const Hit uncounted = bvh.intersect<TriangleTest::watertight>(ray, none);
        CHECK(counted.triangle == uncounted.triangle);
        CHECK(counters.nodes_visited >= 1);
        if (counted.is_hit()) {
            ++hits;
            CHECK(counters.triangles_tested >= 1);
            CHECK(counters.nodes_visited >= 3);  // root, then both children of every node on the way down
        }
        total += counters;
    }
    REQUIRE(hits > 100);
    // The hierarchy prunes: far fewer triangle tests than the brute force's, and an odd number of
    // box tests per ray (the root plus pairs of children).
    CHECK(double(total.triangles_tested) < 0.05 * double(rays.size() * mesh.triangle_count()));
    TraversalCounters one;
    bvh.intersect<TriangleTest::watertight>(rays[0], one);
    CHECK(one.nodes_visited % 2 == 1);
}
