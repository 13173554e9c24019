#pragma once
// The flattened kd-tree node: 8 bytes, as in pbrt's KdAccelNode. An interior node holds its split
// plane and the index of its first child; the two children are adjacent (first, first + 1), so one
// index suffices. A leaf holds a run of triangle ids in the tree's one leaf-triangle list.
//
//   word 0: split position (float bits) for an interior node, triangle count for a leaf
//   word 1: index << 4 | empty << 2 | tag, where tag 0..2 is the split axis and 3 marks a leaf;
//           the index is the first child (interior) or the offset of the run in the
//           leaf-triangle list (leaf). In an interior node, bit 0 of `empty` says the child below
//           is an empty leaf, bit 1 the child above: the traversals skip such a child without
//           fetching it. Empty leaves are most of the leaves a ray visits on the study's scenes
//           (the empty-space bonus makes them to cut empty space off), 7.5 of 9.2 a primary ray
//           on Room (bench/experiments/kdtree.md).
#include <bit>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace trident {

/// The deepest level the kd-tree builder makes (the root is depth 0). The traversal stack holds at
/// most one entry per level, so this is also its size.
inline constexpr int kKdMaxDepth = 64;

class KdNode {
    static constexpr int kIndexShift = 4;

public:
    /// Largest child index or leaf offset the 28 index bits hold.
    static constexpr std::uint32_t kMaxIndex = (1u << (32 - kIndexShift)) - 1;

    /// Throws std::length_error when first_child does not fit in 28 bits. below_empty and
    /// above_empty say that the child is an empty leaf.
    static KdNode interior(int axis, float split, std::size_t first_child, bool below_empty = false,
                           bool above_empty = false) {
        check_index(first_child, "node count");
        return KdNode(std::bit_cast<std::uint32_t>(split), std::uint32_t(first_child) << kIndexShift |
                                                               std::uint32_t(above_empty) << 3 |
                                                               std::uint32_t(below_empty) << 2 | std::uint32_t(axis));
    }
    /// Throws std::length_error when offset does not fit in 28 bits.
    static KdNode leaf(std::uint32_t triangle_count, std::size_t offset) {
        check_index(offset, "leaf-triangle list");
        return KdNode(triangle_count, std::uint32_t(offset) << kIndexShift | kLeafTag);
    }

    bool is_leaf() const { return (tagged_index_ & 3u) == kLeafTag; }
    bool is_empty_leaf() const { return is_leaf() && triangle_count() == 0; }

    // Interior nodes.
    int axis() const { return int(tagged_index_ & 3u); }
    float split() const { return std::bit_cast<float>(payload_); }
    std::uint32_t below_child() const { return tagged_index_ >> kIndexShift; }        // coordinates <= split
    std::uint32_t above_child() const { return (tagged_index_ >> kIndexShift) + 1; }  // coordinates >= split
    bool below_empty() const { return (tagged_index_ >> 2 & 1u) != 0; }  // the child below is an empty leaf
    bool above_empty() const { return (tagged_index_ >> 3 & 1u) != 0; }  // the child above is an empty leaf

    // Leaves.
    std::uint32_t triangle_count() const { return payload_; }
    std::uint32_t triangle_offset() const { return tagged_index_ >> kIndexShift; }

    bool operator==(const KdNode&) const = default;

private:
    static constexpr std::uint32_t kLeafTag = 3;

    KdNode(std::uint32_t payload, std::uint32_t tagged_index) : payload_(payload), tagged_index_(tagged_index) {}

    static void check_index(std::size_t index, const char* what) {
        if (index > kMaxIndex)
            throw std::length_error("kd-tree: the " + std::string(what) + " exceeds the " +
                                    std::to_string(kMaxIndex + 1) + " entries a KdNode can index (28 bits)");
    }

    std::uint32_t payload_;
    std::uint32_t tagged_index_;
};
static_assert(sizeof(KdNode) == 8, "pbrt's 8-byte kd node: eight per cache line");

}  // namespace trident
