#pragma once
// The kd-tree builder: exact SAH over split-plane events on all three axes, in O(N log N) after
// Wald and Havran, "On building fast kd-trees for ray tracing, and on doing that in O(N log N)"
// (IEEE RT 2006). Events are sorted once at the root and kept sorted while splitting: a node's
// sorted lists are split into its children's by one linear pass, and only the triangles that
// straddle the plane get new events (clipped, sorted, merged). Subtrees are built in parallel with
// oneTBB; the tree does not depend on the thread count.
#include <span>
#include <vector>

#include "accel/kdtree/kd_node.h"
#include "accel/kdtree/kd_options.h"
#include "core/aabb.h"
#include "core/mesh.h"
#include "core/ray.h"

namespace trident {

struct KdBuildResult {
    /// Depth-first; nodes[0] is the root; empty when no triangle has finite corners.
    std::vector<KdNode> nodes;
    /// Every leaf's triangles as indices into `triangles`, one run per leaf, ascending within a run.
    std::vector<TriangleId> leaf_triangles;
    /// The triangles with finite corners in the order the builder chose (Morton order of their
    /// centres, so that triangles near in space are near in memory), and each one's file index.
    std::vector<Triangle> triangles;
    std::vector<TriangleId> triangle_ids;
    /// The root cell: the bounds of the triangles with finite corners.
    Aabb bounds;
};

/// Triangles with a non-finite corner are left out (no ray can hit them). Expects valid options.
KdBuildResult build_kdtree(std::span<const Triangle> triangles, const KdTreeOptions& options);

}  // namespace trident
