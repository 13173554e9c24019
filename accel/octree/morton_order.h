#pragma once
// Triangles sorted along the Morton (Z-order) curve of the octree's own cells: with child bit 0 =
// x, 1 = y, 2 = z, the curve visits cells in the order the octree stores them, so the builder's
// passes over a level and the traversal's leaves read the triangle array nearly in sequence
// instead of jumping through a file-ordered mesh.
#include <cstdint>
#include <span>
#include <vector>

#include "accel/octree/octree_node.h"
#include "core/mesh.h"

namespace trident {

/// Bits per axis of the Morton key: cells of 1/1024 of the cube's edge, deeper than any default.
inline constexpr int kMortonBitsPerAxis = 10;

/// The Morton key of a point in the cube (clamped to it): bit 3i + a holds bit i of the point's
/// quantized coordinate on axis a.
std::uint32_t morton_key(const Vec3f& point, const OctreeCube& cube);

struct MortonSorted {
    std::vector<std::uint32_t> indices;  // the triangles' indices along the curve
    std::vector<std::uint32_t> keys;     // their keys, ascending
};

/// `indices` (of `triangles`) sorted by the Morton key of the triangles' centroids; ties keep
/// their order (a stable radix sort), so the result is deterministic.
MortonSorted sort_by_morton_key(std::span<const Triangle> triangles, std::vector<std::uint32_t> indices,
                                const OctreeCube& cube);

/// occupied[d] = the number of distinct cells at depth d (0 to kMortonBitsPerAxis) that hold
/// at least one of the keys: cells sharing a key prefix are adjacent once sorted.
std::vector<std::size_t> occupied_cells_per_depth(std::span<const std::uint32_t> sorted_keys);

}  // namespace trident
