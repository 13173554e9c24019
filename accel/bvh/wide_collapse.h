#pragma once
// Collapsing the binary SAH tree (bvh.h) into a wide one (wide_node.h): which binary subtrees
// become leaves of triangle blocks and which binary nodes are opened into a wide node's children.
//
// Which binary subtrees become leaves and which binary nodes a wide node's children are is decided
// by the dynamic programme of Ylitie, Karras and Laine 2017 ("Efficient incoherent ray traversal
// on GPUs through compressed wide BVHs", section 3.1), bottom-up over the binary tree: the SAH of
// every subtree given 1 to Width child slots, where a subtree takes one slot as a leaf (a block
// test per block, each weighed by the leaf's area) or as a wide node of its own (a node step,
// then its Width slots shared between its binary children), or shares more slots between its
// children; each block and each node also costs its memory, which decides only in the smallest
// subtrees (kBlockMemoryCost in wide_collapse.cpp). Top-down, each wide node then takes the
// children that the root's cheapest form names.
// Against opening the largest child until Width are held, it fills nodes with 7 children on
// average instead of 3.8 (bench/experiments/bvh-traversal.md).
//
// Blocks hold only triangles with area (has_area): no triangle test hits the others, so leaving
// them out changes no answer, and the tests of the wide tree skip their own lane-by-lane check
// (ZeroAreaTriangles::left_out_by_caller), which a packet's lanes repeated for every triangle
// they hit. A leaf of zero-area triangles only keeps its box and no block.
#include <cstddef>
#include <cstdint>
#include <span>

#include "accel/bvh/bvh_node.h"
#include "accel/bvh/wide_node.h"
#include "core/huge_page_array.h"
#include "core/mesh.h"

namespace trident::bvh {

/// What a wide tree is made of, with the figures its statistics need.
template <std::size_t Width, std::size_t BlockSize>
struct WideArrays {
    HugePageArray<WideNode<Width>> nodes;  // breadth-first: the root is node 0, then level by level
    HugePageArray<TriangleBlock<BlockSize>> blocks;
    std::size_t leaves = 0;
    std::size_t references = 0;  // triangles in blocks: those with area
    std::size_t max_depth = 0;  // of wide nodes and leaves, the root node at 0
    std::size_t max_leaf_triangles = 0;
    std::size_t child_slots_used = 0;  // over all nodes, for the mean children per node
    double sah_cost = 0.0;             // the wide tree's SAH with the collapse's own costs
};

/// The wide tree over the binary tree `nodes` (depth-first, root first) whose leaves cover the
/// triangles `ids` of `mesh` in leaf order (the corners are read from the mesh: the binary tree's
/// leaf-order copy of them, 36 bytes a triangle, would be written only to be read once). A leaf
/// gathers a binary subtree of at most min(leaf_limit, 2 * BlockSize) triangles (a binary leaf
/// larger than that stays one leaf), each id once where spatial splits put a triangle in several
/// of the subtree's binary leaves. Blocks are filled in parallel; the result does not depend on
/// the number of threads. An empty tree gives no nodes.
template <std::size_t Width, std::size_t BlockSize>
WideArrays<Width, BlockSize> collapse_to_wide(std::span<const BvhNode> nodes, const Mesh& mesh,
                                              std::span<const TriangleId> ids, std::uint32_t leaf_limit);

/// How many nodes lie at depths below `levels` (the root at depth 0) of a tree whose nodes are
/// numbered breadth-first, as collapse_to_wide numbers them: nodes 0 to that count - 1.
template <std::size_t Width>
std::size_t nodes_above_level(std::span<const WideNode<Width>> nodes, std::size_t levels) {
    if (nodes.empty() || levels == 0) return 0;
    std::size_t level_begin = 0, level_end = 1;
    for (std::size_t level = 1; level < levels && level_begin != level_end; ++level) {
        std::size_t next_end = level_end;
        for (std::size_t n = level_begin; n != level_end; ++n)
            for (const ChildRef child : nodes[n].child)
                if (!child.is_empty() && !child.is_leaf()) ++next_end;
        level_begin = level_end;
        level_end = next_end;
    }
    return level_end;
}

}  // namespace trident::bvh
