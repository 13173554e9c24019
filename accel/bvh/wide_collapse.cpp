#include "accel/bvh/wide_collapse.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/intersect_triangle.h"

namespace trident::bvh {

namespace {

/// In double: a float area overflows for boxes wider than about 1e19.
double area_of(const Aabb& box) {
    const double x = double(box.hi.x) - box.lo.x, y = double(box.hi.y) - box.lo.y, z = double(box.hi.z) - box.lo.z;
    return 2.0 * (x * y + y * z + z * x);
}

/// Per binary node: the leaf-order triangles it spans, those of them with area (what its blocks
/// hold), and whether it becomes one wide leaf.
struct BinaryFacts {
    std::vector<std::uint32_t> spanned, triangles;
    std::vector<char> is_leaf;
};

/// Per leaf-order triangle: whether it has area, in parallel.
std::vector<char> triangles_with_area(std::span<const Triangle> triangles) {
    std::vector<char> out(triangles.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles.size(), 4096), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) out[i] = has_area(triangles[i]);
    });
    return out;
}

/// Costs relative to one wide node step (all Width boxes against a ray) and to one block test.
constexpr double kNodeStepCost = 1.0, kBlockTestCost = 1.0;

/// Bottom-up (children follow their parent in depth-first order): each subtree's cheapest form,
/// as one leaf or as interior levels. A binary level inside a wide node costs the node step shared
/// among the Width - 1 binary splits a full node holds.
template <std::size_t Width, std::size_t BlockSize>
BinaryFacts decide_leaves(std::span<const BvhNode> nodes, std::span<const char> with_area, std::uint32_t leaf_limit) {
    const std::uint32_t largest_leaf =
        std::min<std::uint32_t>({2 * BlockSize, leaf_limit, ChildRef::kMaxLeafTriangles});
    constexpr double kLevelCost = kNodeStepCost / double(Width - 1);
    BinaryFacts facts{std::vector<std::uint32_t>(nodes.size()), std::vector<std::uint32_t>(nodes.size()),
                      std::vector<char>(nodes.size())};
    std::vector<double> cost(nodes.size());
    for (std::size_t i = nodes.size(); i-- > 0;) {
        const BvhNode& node = nodes[i];
        const double area = area_of(node.bounds);
        if (node.is_leaf()) {
            facts.spanned[i] = node.triangle_count();
            const auto first = with_area.begin() + node.first_triangle();
            facts.triangles[i] = std::uint32_t(std::count(first, first + node.triangle_count(), char(1)));
            if (facts.triangles[i] > ChildRef::kMaxLeafTriangles)
                throw std::length_error("wide BVH: a leaf of " + std::to_string(facts.triangles[i]) + " triangles");
            facts.is_leaf[i] = 1;
            cost[i] = area * kBlockTestCost * double((facts.triangles[i] + BlockSize - 1) / BlockSize);
            continue;
        }
        const std::size_t left = i + 1, right = node.right_child();
        facts.spanned[i] = facts.spanned[left] + facts.spanned[right];
        facts.triangles[i] = facts.triangles[left] + facts.triangles[right];
        const double descend = area * kLevelCost + cost[left] + cost[right];
        const double as_leaf = area * kBlockTestCost * double((facts.triangles[i] + BlockSize - 1) / BlockSize);
        facts.is_leaf[i] = facts.triangles[i] <= largest_leaf && as_leaf <= descend;
        cost[i] = facts.is_leaf[i] ? as_leaf : descend;
    }
    return facts;
}

/// A wide node to fill: its index and the binary nodes that become its children.
template <std::size_t Width>
struct PlannedNode {
    std::uint32_t index;
    std::uint32_t depth;
    std::uint32_t children[Width];
    std::uint32_t child_count;
};

/// A leaf to fill: the binary subtree's leaf-order triangles (first, count), how many of them have
/// area, its first block.
struct PlannedLeaf {
    std::uint32_t first_triangle, spanned, triangle_count, first_block;
};

/// Opens, among the node's children that are not leaves, the one of largest surface area into its
/// two children, until the node holds Width or only leaves.
template <std::size_t Width>
void open_largest_children(PlannedNode<Width>& node, const BinaryFacts& facts, std::span<const BvhNode> nodes) {
    while (node.child_count < Width) {
        int widest = -1;
        double widest_area = -1.0;
        for (std::uint32_t k = 0; k < node.child_count; ++k) {
            const std::uint32_t b = node.children[k];
            if (facts.is_leaf[b]) continue;
            const double area = area_of(nodes[b].bounds);
            if (area > widest_area) widest = int(k), widest_area = area;
        }
        if (widest < 0) return;
        const std::uint32_t opened = node.children[widest];
        node.children[widest] = opened + 1;
        node.children[node.child_count++] = nodes[opened].right_child();
    }
}

/// The first leaf-order triangle of a binary subtree: its leftmost leaf's.
std::uint32_t first_triangle_of(std::span<const BvhNode> nodes, std::uint32_t i) {
    while (!nodes[i].is_leaf()) ++i;  // the left child follows its parent
    return nodes[i].first_triangle();
}

}  // namespace

template <std::size_t Width, std::size_t BlockSize>
WideArrays<Width, BlockSize> collapse_to_wide(std::span<const BvhNode> nodes, std::span<const Triangle> triangles,
                                              std::span<const TriangleId> ids, std::uint32_t leaf_limit) {
    static_assert(Width >= 2 && Width <= 16 && BlockSize >= 1);
    WideArrays<Width, BlockSize> out;
    if (nodes.empty()) return out;
    const std::vector<char> with_area = triangles_with_area(triangles);
    const BinaryFacts facts = decide_leaves<Width, BlockSize>(nodes, with_area, leaf_limit);
    const double root_area = area_of(nodes[0].bounds);
    const auto weight = [&](std::uint32_t binary) {
        return root_area > 0.0 ? area_of(nodes[binary].bounds) / root_area : 1.0;
    };

    // Plan serially (a few operations a wide node), children of a node numbered side by side.
    std::vector<PlannedNode<Width>> planned;
    std::vector<PlannedLeaf> leaves;
    std::vector<ChildRef> refs(Width, ChildRef::empty());  // per planned node, Width slots
    std::uint32_t block_count = 0;
    planned.push_back({0, 0, {}, 0});
    // The root: a binary leaf (or a root that is one wide leaf) becomes the single child of node 0.
    if (facts.is_leaf[0]) {
        planned[0].children[0] = 0;
        planned[0].child_count = 1;
    } else {
        planned[0].children[0] = 1;
        planned[0].children[1] = nodes[0].right_child();
        planned[0].child_count = 2;
    }
    out.sah_cost += weight(0) * kNodeStepCost;
    for (std::size_t next = 0; next < planned.size(); ++next) {
        open_largest_children(planned[next], facts, nodes);
        const PlannedNode<Width> node = planned[next];  // a copy: planning its children grows `planned`
        out.child_slots_used += node.child_count;
        for (std::uint32_t k = 0; k < node.child_count; ++k) {
            const std::uint32_t b = node.children[k];
            if (facts.is_leaf[b]) {
                const std::uint32_t count = facts.triangles[b];
                if (block_count > ChildRef::kMaxFirstBlock)
                    throw std::length_error("wide BVH: more than " + std::to_string(ChildRef::kMaxFirstBlock) +
                                            " triangle blocks");
                refs[next * Width + k] = ChildRef::leaf(block_count, count);
                leaves.push_back({first_triangle_of(nodes, b), facts.spanned[b], count, block_count});
                out.references += count;
                const std::uint32_t blocks = (count + BlockSize - 1) / BlockSize;
                block_count += blocks;
                out.sah_cost += weight(b) * kBlockTestCost * double(blocks);
                out.max_depth = std::max<std::size_t>(out.max_depth, node.depth + 1);
                out.max_leaf_triangles = std::max<std::size_t>(out.max_leaf_triangles, count);
            } else {
                const auto index = std::uint32_t(planned.size());
                refs[next * Width + k] = ChildRef::node(index);
                PlannedNode<Width> child{index, node.depth + 1, {}, 2};
                child.children[0] = b + 1;
                child.children[1] = nodes[b].right_child();
                out.sah_cost += weight(b) * kNodeStepCost;
                out.max_depth = std::max<std::size_t>(out.max_depth, child.depth);
                planned.push_back(child);
            }
        }
        refs.resize(planned.size() * Width, ChildRef::empty());
    }
    out.leaves = leaves.size();

    // Fill in parallel: boxes of every node, corners and ids of every block.
    out.nodes.resize(planned.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, planned.size(), 1024), [&](const auto& range) {
        for (std::size_t n = range.begin(); n != range.end(); ++n) {
            WideNode<Width>& node = out.nodes[n];
            for (std::size_t k = 0; k < Width; ++k) {
                const bool used = k < planned[n].child_count;
                const Aabb box = used ? nodes[planned[n].children[k]].bounds : Aabb{};
                for (int axis = 0; axis < 3; ++axis) {
                    node.bounds[lower_row(axis)][k] = box.lo[axis];
                    node.bounds[upper_row(axis)][k] = box.hi[axis];
                }
                node.child[k] = refs[n * Width + k];
            }
        }
    });
    out.blocks.resize(block_count);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 1024), [&](const auto& range) {
        for (std::size_t l = range.begin(); l != range.end(); ++l) {
            const PlannedLeaf& leaf = leaves[l];
            std::uint32_t source = leaf.first_triangle;
            [[maybe_unused]] const std::uint32_t end = leaf.first_triangle + leaf.spanned;
            for (std::uint32_t k = 0; k < (leaf.triangle_count + BlockSize - 1) / BlockSize * BlockSize; ++k) {
                // The next triangle with area; past the leaf's last, the padding repeats it.
                if (k != 0 && k < leaf.triangle_count) ++source;
                while (k < leaf.triangle_count && !with_area[source]) ++source;
                assert(source < end);
                TriangleBlock<BlockSize>& block = out.blocks[leaf.first_block + k / BlockSize];
                const std::size_t lane = k % BlockSize;
                const Triangle& tri = triangles[source];
                for (int axis = 0; axis < 3; ++axis) {
                    block.a[axis][lane] = tri.a[axis];
                    block.b[axis][lane] = tri.b[axis];
                    block.c[axis][lane] = tri.c[axis];
                }
                block.id[lane] = ids[source];
            }
        }
    });
    return out;
}

template WideArrays<4, 4> collapse_to_wide<4, 4>(std::span<const BvhNode>, std::span<const Triangle>,
                                                 std::span<const TriangleId>, std::uint32_t);
template WideArrays<8, 4> collapse_to_wide<8, 4>(std::span<const BvhNode>, std::span<const Triangle>,
                                                 std::span<const TriangleId>, std::uint32_t);

}  // namespace trident::bvh
