#pragma once
// How a kd-tree is built: the SAH cost model of the reference study (after pbrt) and its limits.
#include <cstddef>

namespace trident {

struct KdTreeOptions {
    /// SAH costs of one triangle test and one traversal step (the study: 80 and 1).
    float intersection_cost = 80.0f;
    float traversal_cost = 1.0f;
    /// A split with an empty side costs (1 - empty_bonus) times as much (Wald and Havran 2006).
    float empty_bonus = 0.5f;
    /// Deepest leaf; negative means round(8 + 1.3 log2(N)) (pbrt) plus depth_offset, kept within
    /// 0..kKdMaxDepth - 1.
    int max_depth = -1;
    /// Levels added to pbrt's formula (negative: fewer); 0, the study's, by default. The formula
    /// ends every tree on the study's scenes, so the bench's kd-depth sweep moves it to measure
    /// what deeper or shallower trees give (bench/experiments/kdtree.md).
    int depth_offset = 0;
    /// Consecutive splits costing more than a leaf before the node becomes one anyway (pbrt).
    int max_bad_refines = 3;
    /// A node with at most this many triangles becomes a leaf.
    std::size_t leaf_triangles = 1;
    /// Havran's perfect splits: a triangle straddling a split plane is clipped to each child's box
    /// (Sutherland-Hodgman), so its bounds are tight and a child it misses drops it. Off: its
    /// bounding box is only clamped to the child's box.
    bool perfect_splits = false;
    /// Nodes with at least this many triangles build their two children as parallel tasks. Only
    /// the speed depends on it: the tree is the same for every value and every thread count.
    std::size_t parallel_triangles = 2048;
    /// Nodes with at most this many triangles (up to kMaxSmallNodeTriangles; 0: none) are built,
    /// with their subtrees, from their triangles' box ends instead of event lists (kd_build.cpp).
    /// Only the speed depends on it: the tree is the same for every value.
    static constexpr std::size_t kMaxSmallNodeTriangles = 8;
    std::size_t small_node_triangles = kMaxSmallNodeTriangles;

    /// Throws std::invalid_argument naming the first field out of range.
    void validate() const;
    /// The depth limit for n triangles: max_depth, or pbrt's formula when it is negative.
    int depth_limit(std::size_t n) const;
};

}  // namespace trident
