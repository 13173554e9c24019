#pragma once
// The flattened octree: 8-byte nodes, children of a node stored side by side in child-index
// order with the empty ones left out, leaves pointing into one triangle-index list. Cells are
// never stored: they follow from the root cube and the path to a node.
//
// Child numbering: bit 0 of the child index is x, bit 1 is y, bit 2 is z; a set bit means the
// upper half of the parent along that axis (child 5 = upper x, lower y, upper z).
#include <bit>
#include <cstdint>

#include "core/vec3.h"

namespace trident {

/// A cubic cell: lower corner and edge length. The root cube is the scene's box made a cube.
struct OctreeCube {
    Vec3f lo;
    float size = 0.0f;

    /// The centre plane coordinate along each axis (also the upper children's lower corner).
    Vec3f mid() const { return lo + Vec3f(size * 0.5f); }
};

/// Child `child`'s cell. Builder and traversal both derive cells through this one function, so
/// they agree on every plane to the last bit.
inline OctreeCube child_cube(const OctreeCube& parent, unsigned child) {
    const float half = parent.size * 0.5f;
    const Vec3f mid = parent.mid();
    return {{child & 1u ? mid.x : parent.lo.x, child & 2u ? mid.y : parent.lo.y, child & 4u ? mid.z : parent.lo.z},
            half};
}

/// Interior: `index` is the slot of the first stored child, `bits` holds the 8-bit child mask.
/// Leaf: `index` is the offset of its triangles in the triangle-index list, `bits` holds the count
/// and the leaf flag (bit 31).
struct OctreeNode {
    std::uint32_t index = 0;
    std::uint32_t bits = 0;

    static constexpr std::uint32_t kLeafFlag = 0x80000000u;
    static constexpr std::uint32_t kMaxLeafCount = kLeafFlag - 1;

    static OctreeNode interior(std::uint32_t first_child, unsigned child_mask) { return {first_child, child_mask}; }
    static OctreeNode leaf(std::uint32_t offset, std::uint32_t count) { return {offset, count | kLeafFlag}; }

    bool is_leaf() const { return (bits & kLeafFlag) != 0; }

    unsigned child_mask() const { return bits & 0xFFu; }
    std::uint32_t first_child() const { return index; }
    bool has_child(unsigned child) const { return (child_mask() >> child) & 1u; }
    /// Slot of child `child` (which must be stored): the stored children before it come first.
    std::uint32_t child_slot(unsigned child) const {
        return index + std::uint32_t(std::popcount(child_mask() & ((1u << child) - 1u)));
    }

    std::uint32_t triangle_offset() const { return index; }
    std::uint32_t triangle_count() const { return bits & ~kLeafFlag; }

    friend bool operator==(const OctreeNode&, const OctreeNode&) = default;
};
static_assert(sizeof(OctreeNode) == 8, "octree nodes are 8 bytes");

}  // namespace trident
