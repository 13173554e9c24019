#pragma once
// What every acceleration structure reports about itself, and the per-ray counters of its
// traversal. Counters are a template parameter of the traversals: NoCounters compiles to
// nothing, so counting costs nothing when it is off.
#include <cstddef>
#include <cstdint>
#include <string>

namespace trident {

struct AccelStats {
    std::string structure;            // "bvh", "kdtree", "octree", "brute"
    std::size_t triangles = 0;        // input triangles
    std::size_t nodes = 0;            // interior nodes + leaves
    std::size_t leaves = 0;
    std::size_t empty_leaves = 0;
    std::size_t max_depth = 0;        // root is depth 0
    std::size_t references = 0;       // triangle references held by leaves (>= triangles when split)
    std::size_t max_leaf_size = 0;
    double mean_leaf_size = 0.0;      // references per non-empty leaf
    double sah_cost = 0.0;            // cost of the finished tree under the builder's own cost model
    std::size_t bytes = 0;            // nodes + index lists + leaf triangle copies
    double build_ms = 0.0;            // from the mesh in memory to the flattened structure
    // Wide trees only (0 elsewhere): children per interior node, and the share of the triangle
    // blocks' lanes holding a triangle of their own rather than padding.
    double mean_children = 0.0;
    double block_fill = 0.0;
    // The builder that made the tree where a structure has several (the BVHs: to_string(BvhBuilder),
    // automatic resolved), empty elsewhere.
    std::string builder;

    double references_per_triangle() const { return triangles ? double(references) / double(triangles) : 0.0; }
    double bytes_per_triangle() const { return triangles ? double(bytes) / double(triangles) : 0.0; }
    /// Everything above on one line, for `trident info` and build logs.
    std::string to_line() const;
};

struct TraversalCounters {
    std::uint64_t nodes_visited = 0;
    std::uint64_t triangles_tested = 0;
    void visit_node() { ++nodes_visited; }
    void test_triangle() { ++triangles_tested; }
    TraversalCounters& operator+=(const TraversalCounters& o) {
        nodes_visited += o.nodes_visited;
        triangles_tested += o.triangles_tested;
        return *this;
    }
};

struct NoCounters {
    void visit_node() {}
    void test_triangle() {}
};

}  // namespace trident
