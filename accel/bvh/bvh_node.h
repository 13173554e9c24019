#pragma once
// The flattened BVH node: 32 bytes, stored in one array in depth-first order so that an interior
// node's left child is the next node and only the right child needs an index (pbrt-v4's
// LinearBVHNode). Leaves index a run of triangles stored contiguously in leaf order.
#include <cstdint>

#include "core/aabb.h"

namespace trident {

/// The deepest node the builder makes (the root is depth 0). The traversal stack holds at most
/// one entry per level, so this is also its size; the builder switches from SAH to median splits
/// early enough that no leaf lies deeper (see split_node in tree_builder.h).
inline constexpr std::uint32_t kBvhMaxDepth = 64;

struct BvhNode {
    Aabb bounds;
    std::uint32_t index;       // leaf: first triangle in leaf order; interior: right child
    std::uint32_t count_axis;  // triangle count << 2 | split axis; a count of 0 marks an interior node

    static BvhNode leaf(const Aabb& bounds, std::uint32_t first_triangle, std::uint32_t triangle_count) {
        return {bounds, first_triangle, triangle_count << 2};
    }
    static BvhNode interior(const Aabb& bounds, int split_axis, std::uint32_t right_child) {
        return {bounds, right_child, std::uint32_t(split_axis)};
    }

    bool is_leaf() const { return count_axis >= 4; }
    std::uint32_t triangle_count() const { return count_axis >> 2; }
    std::uint32_t first_triangle() const { return index; }
    /// The axis the children were split on; its direction sign picks the near child.
    int split_axis() const { return int(count_axis & 3u); }
    std::uint32_t right_child() const { return index; }
};
static_assert(sizeof(BvhNode) == 32, "two nodes per 64-byte cache line");

}  // namespace trident
