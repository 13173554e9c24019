#pragma once
// The top-down recursion both BVH builders share, written once over a Splitter (binned or sweep
// SAH): the leaf-or-split decision with its fallbacks, parallel subtrees, and the flattening into
// depth-first order.
//
// Large nodes are split as tasks (oneTBB) into a small tree of pending nodes; below
// kParallelSubtreeMin triangles a subtree is built serially straight into its own depth-first
// array. One pass then places the pending nodes and copies the subtree arrays into the final
// array. Which nodes become tasks depends only on their size, and every split is computed from
// exact unions and counts, so the flattened tree is the same for any number of threads.
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <bit>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "accel/bvh/build_primitives.h"
#include "accel/bvh/bvh_node.h"
#include "accel/bvh/bvh_options.h"
#include "core/huge_page_array.h"

namespace trident::bvh {

template <class Splitter>
class TreeBuilder {
public:
    static constexpr std::uint32_t kParallelSubtreeMin = 4096;

    TreeBuilder(Splitter& splitter, const BvhOptions& options) : splitter_(splitter), options_(options) {}

    /// The flattened tree over `root` (no nodes for an empty range). `depth`: the root's depth in
    /// a larger tree (the spatial split builder hands subtrees over), which the depth bound counts.
    HugePageArray<BvhNode> build(const BuildRange& root, std::uint32_t depth = 0) {
        if (root.count() == 0) return {};
        const std::unique_ptr<PendingNode> top = build_pending(root, depth);
        HugePageArray<BvhNode> nodes(node_count(*top));
        std::vector<SubtreeCopy> copies;
        place(*top, 0, nodes, copies);
        tbb::parallel_for(std::size_t(0), copies.size(), [&](std::size_t i) {
            const SubtreeCopy& copy = copies[i];
            BvhNode* out = nodes.data() + copy.offset;
            for (const BvhNode& node : *copy.subtree) {
                *out = node;
                if (!node.is_leaf()) out->index += copy.offset;  // leaves index triangles, not nodes
                ++out;
            }
        });
        return nodes;
    }

private:
    /// A node split as a task: either an interior node with two pending children, or a subtree
    /// already flattened (right-child indices relative to its first node).
    struct PendingNode {
        BvhNode node{};
        std::unique_ptr<PendingNode> left, right;
        std::vector<BvhNode> subtree;
    };
    struct SubtreeCopy {
        const std::vector<BvhNode>* subtree;
        std::uint32_t offset;
    };

    /// Split a node, or nothing when it should be a leaf. A node that fits one block of the wide
    /// BVH is split only where the collapse's cost says so (BvhOptions::split_beats_block);
    /// otherwise SAH decides (leaf cost
    /// intersection_cost * N * A against the best split's cost); a node SAH would leave too large
    /// falls back to a median split. Depth bound: while depth + ceil(log2 N) <= kBvhMaxDepth holds,
    /// median splits (which halve N) can always finish the subtree within kBvhMaxDepth, so an SAH
    /// split is taken only while it keeps that true for its children.
    std::optional<ChildRanges> split_node(const BuildRange& range, std::uint32_t depth) {
        const std::uint32_t count = range.count();
        if (count <= 1) return std::nullopt;
        if (depth + 1 + std::uint32_t(std::bit_width(count - 1)) <= kBvhMaxDepth) {
            const auto split = splitter_.find_sah_split(range);
            if (options_.fits_one_block(count)) {
                if (!(split.cost < kInfinity)) return std::nullopt;
                ChildRanges children = splitter_.partition(range, split);  // a leaf keeps the range as reordered
                if (BvhOptions::split_beats_block(children.left.bounds.surface_area(),
                                                  children.right.bounds.surface_area(), range.bounds.surface_area()))
                    return children;
                return std::nullopt;
            }
            const float leaf_cost = options_.intersection_cost * float(count) * range.bounds.surface_area();
            if (split.cost < leaf_cost) return splitter_.partition(range, split);
        }
        if (count <= std::uint32_t(options_.max_leaf_size)) return std::nullopt;
        return splitter_.partition_median(range);
    }

    void build_serial(std::vector<BvhNode>& out, const BuildRange& range, std::uint32_t depth) {
        const std::optional<ChildRanges> children = split_node(range, depth);
        if (!children) {
            out.push_back(BvhNode::leaf(range.bounds, range.begin, range.count()));
            return;
        }
        const std::size_t index = out.size();
        out.push_back(BvhNode::interior(range.bounds, children->axis, 0));
        build_serial(out, children->left, depth + 1);
        out[index].index = std::uint32_t(out.size());
        build_serial(out, children->right, depth + 1);
    }

    std::unique_ptr<PendingNode> build_pending(const BuildRange& range, std::uint32_t depth) {
        auto pending = std::make_unique<PendingNode>();
        if (range.count() < kParallelSubtreeMin) {
            pending->subtree.reserve(2 * std::size_t(range.count()) - 1);  // a binary tree's bound
            build_serial(pending->subtree, range, depth);
            return pending;
        }
        const std::optional<ChildRanges> children = split_node(range, depth);
        if (!children) {
            pending->subtree.push_back(BvhNode::leaf(range.bounds, range.begin, range.count()));
            return pending;
        }
        pending->node = BvhNode::interior(range.bounds, children->axis, 0);
        tbb::parallel_invoke([&] { pending->left = build_pending(children->left, depth + 1); },
                             [&] { pending->right = build_pending(children->right, depth + 1); });
        return pending;
    }

    static std::size_t node_count(const PendingNode& pending) {
        if (!pending.left) return pending.subtree.size();
        return 1 + node_count(*pending.left) + node_count(*pending.right);
    }

    /// Writes the pending nodes depth-first from `offset` and queues the subtree copies; returns
    /// the offset after the last node of this subtree.
    static std::uint32_t place(const PendingNode& pending, std::uint32_t offset, HugePageArray<BvhNode>& nodes,
                               std::vector<SubtreeCopy>& copies) {
        if (!pending.left) {
            copies.push_back({&pending.subtree, offset});
            return offset + std::uint32_t(pending.subtree.size());
        }
        nodes[offset] = pending.node;
        const std::uint32_t right = place(*pending.left, offset + 1, nodes, copies);
        nodes[offset].index = right;
        return place(*pending.right, right, nodes, copies);
    }

    Splitter& splitter_;
    const BvhOptions& options_;
};

}  // namespace trident::bvh
