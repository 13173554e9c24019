#pragma once
// What a flattened BVH costs: its SAH cost and the figures of AccelStats, read off the arrays.
#include <cstddef>
#include <span>

#include "accel/accel_stats.h"
#include "accel/bvh/bvh_node.h"
#include "accel/bvh/bvh_options.h"

namespace trident {

/// The SAH cost of a tree (Goldsmith and Salmon 1987; MacDonald and Booth 1990): the sum over
/// nodes of area(node) / area(root) times traversal_cost for an interior node, or times
/// intersection_cost * triangles for a leaf. 0 for an empty tree; a root of zero area (all
/// triangles on one line or point) weighs every node 1.
double bvh_sah_cost(std::span<const BvhNode> nodes, float traversal_cost, float intersection_cost);

/// Every AccelStats field but build_ms, for a tree over `triangle_count` triangles whose leaves
/// hold copies of the corners and the file ids.
AccelStats bvh_stats(std::span<const BvhNode> nodes, std::size_t triangle_count, const BvhOptions& options);

}  // namespace trident
