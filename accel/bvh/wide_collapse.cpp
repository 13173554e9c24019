#include "accel/bvh/wide_collapse.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/intersect_triangle.h"
#include "core/prefetch.h"

namespace trident::bvh {

namespace {

/// Asks for the coordinates of a triangle's corners, each in three arrays (Mesh), ahead of their use.
void prefetch_corners(const Mesh& mesh, const IndexTriple& corners) {
    for (const std::uint32_t v : {corners.v0, corners.v1, corners.v2}) {
        prefetch_line(&mesh.x[v]);
        prefetch_line(&mesh.y[v]);
        prefetch_line(&mesh.z[v]);
    }
}

/// Per leaf-order triangle: whether it has area, in parallel. The areas are found in file order,
/// which reads the mesh front to back, and then looked up in leaf order.
std::vector<char> triangles_with_area(const Mesh& mesh, std::span<const TriangleId> ids) {
    std::vector<char> by_id(mesh.triangle_count()), out(ids.size());
    // File order reads the index triples front to back, but their corners lie anywhere in the
    // vertex arrays: asked for 16 triangles ahead, this pass took 6.3 ms instead of 7.6 on Gallery.
    constexpr std::size_t kCornersAhead = 16;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, by_id.size(), 4096), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            if (i + kCornersAhead < by_id.size()) prefetch_corners(mesh, mesh.triangles[i + kCornersAhead]);
            by_id[i] = has_area(triangle_of(mesh, i));
        }
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ids.size(), 4096), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) out[i] = by_id[ids[i]];
    });
    return out;
}

/// Costs relative to one wide node step (all Width boxes against a ray) and to one block test.
constexpr double kNodeStepCost = 1.0, kBlockTestCost = 1.0;

/// What a block's memory costs in the programme, as a share of the root box's area (a node's, by
/// its bytes against a block's). Beside the SAH of the upper nodes it weighs nothing; in the
/// smallest subtrees, whose areas are a millionth of the root's, it decides between two leaves of
/// a few triangles and one fuller block, or a node of few children and a fuller one, where the SAH
/// barely tells them apart. At 1e-5 the study scenes' trees took 56.2-62.3 bytes a triangle
/// instead of 60.3-64.6, their SAH 0-0.4% higher, the rays' speed unchanged within noise
/// (bench/experiments/bvh-build.md); 1e-6 already took Room from 64.6 to 59.6.
constexpr double kBlockMemoryCost = 1e-5;

/// What the dynamic programme decided for a binary node given `slots` child slots of a wide node
/// (Ylitie et al.'s C(n, i)): with one slot, whether the subtree becomes one leaf or one wide node;
/// with more, how many of them go to the left child (the rest to the right), or kFewerSlots when
/// slots - 1 do as well.
constexpr std::uint8_t kFewerSlots = 0, kAsLeaf = 0xfe, kAsNode = 0xff;

/// Per binary node: the leaf-order triangles it spans, those of them with area (what its blocks
/// hold, as many times as the span repeats a triangle cut by spatial splits: an upper bound of what
/// a leaf holds), and the dynamic programme's decisions.
template <std::size_t Width>
struct CollapsePlan {
    std::vector<std::uint32_t> spanned, triangles;
    /// decision[n][slots - 1]; split[n]: the left child's slots when n is a wide node of its own.
    std::vector<std::array<std::uint8_t, Width>> decision;
    std::vector<std::uint8_t> split;

    bool is_leaf(std::uint32_t n) const { return decision[n][0] == kAsLeaf; }

    /// The binary nodes that fill `slots` of a wide node from the subtree n, appended to `out`.
    void collect(std::span<const BvhNode> nodes, std::uint32_t n, std::size_t slots, std::uint32_t* out,
                 std::uint32_t& count) const {
        while (slots > 1 && decision[n][slots - 1] == kFewerSlots) --slots;
        if (slots == 1) {
            out[count++] = n;
            return;
        }
        const std::size_t left = decision[n][slots - 1];
        collect(nodes, n + 1, left, out, count);
        collect(nodes, nodes[n].right_child(), slots - left, out, count);
    }
};

/// Bottom-up (children follow their parent in depth-first order), the SAH of every subtree given
/// 1 to Width slots (Ylitie, Karras and Laine 2017, section 3.1): a subtree takes one slot as a
/// leaf of blocks or as a wide node of its own (a node step, then its Width slots shared between
/// its children), or more slots shared between its children. Ties go to the leaf, then to fewer
/// slots, then to the smaller left share, so the tree does not depend on rounding order.
///
/// Only the decisions are kept per node. The costs live on a stack of the subtrees whose parent is
/// still ahead (in reverse depth-first order a node's left child is the last subtree finished and
/// its right child the one before), at most one a level. And a subtree of L binary leaves uses at
/// most L slots, so only shares of at most L are weighed: the cheapest share is among them, and
/// more slots than L only fall back to L.
template <std::size_t Width, std::size_t BlockSize>
CollapsePlan<Width> plan_collapse(std::span<const BvhNode> nodes, std::span<const char> with_area,
                                  std::uint32_t leaf_limit) {
    const std::uint32_t largest_leaf =
        std::min<std::uint32_t>({2 * BlockSize, leaf_limit, ChildRef::kMaxLeafTriangles});
    CollapsePlan<Width> plan{std::vector<std::uint32_t>(nodes.size()), std::vector<std::uint32_t>(nodes.size()),
                             std::vector<std::array<std::uint8_t, Width>>(nodes.size()),
                             std::vector<std::uint8_t>(nodes.size())};
    struct SubtreeCost {
        std::array<double, Width> cost;  // cost[slots - 1]
        std::size_t leaves;              // binary leaves: the most slots it can use
    };
    std::vector<SubtreeCost> pending;
    pending.reserve(kBvhMaxDepth + 2);
    const auto blocks_of = [](std::uint32_t triangles) { return double((triangles + BlockSize - 1) / BlockSize); };
    const double block_memory = kBlockMemoryCost * surface_area_in_double(nodes[0].bounds);
    const double node_memory =
        block_memory * double(sizeof(WideNode<Width>)) / double(sizeof(TriangleBlock<BlockSize>));
    for (std::size_t i = nodes.size(); i-- > 0;) {
        const BvhNode& node = nodes[i];
        const double area = surface_area_in_double(node.bounds);
        if (node.is_leaf()) {
            plan.spanned[i] = node.triangle_count();
            const auto first = with_area.begin() + node.first_triangle();
            plan.triangles[i] = std::uint32_t(std::count(first, first + node.triangle_count(), char(1)));
            if (plan.triangles[i] > ChildRef::kMaxLeafTriangles)
                throw std::length_error("wide BVH: a leaf of " + std::to_string(plan.triangles[i]) + " triangles");
            plan.decision[i].fill(kFewerSlots);
            plan.decision[i][0] = kAsLeaf;
            SubtreeCost leaf{{}, 1};
            leaf.cost.fill((area * kBlockTestCost + block_memory) * blocks_of(plan.triangles[i]));
            pending.push_back(leaf);
            continue;
        }
        const SubtreeCost left = pending.back();
        pending.pop_back();
        const SubtreeCost right = pending.back();
        pending.pop_back();
        plan.spanned[i] = plan.spanned[i + 1] + plan.spanned[node.right_child()];
        plan.triangles[i] = plan.triangles[i + 1] + plan.triangles[node.right_child()];
        const std::size_t usable = std::min(Width, left.leaves + right.leaves);
        // shared[s - 1]: the children's cheapest with s slots between them, and the left's share.
        std::array<double, Width> shared;
        std::array<std::uint8_t, Width> left_share{};
        shared[0] = std::numeric_limits<double>::infinity();
        for (std::size_t s = 2; s <= usable; ++s) {
            // The cheapest share, the first at equal cost, kept in selects: branching on each
            // compare mispredicted, and the programme took 20 ms on Gallery instead of 14.5.
            double cheapest = std::numeric_limits<double>::infinity();
            std::uint8_t share = 0;
            const std::size_t first = s > right.leaves ? s - right.leaves : 1, last = std::min(s - 1, left.leaves);
            for (std::size_t k = first; k <= last; ++k) {
                const double c = left.cost[k - 1] + right.cost[s - k - 1];
                const bool cheaper = c < cheapest;
                cheapest = cheaper ? c : cheapest;
                share = cheaper ? std::uint8_t(k) : share;
            }
            shared[s - 1] = cheapest;
            left_share[s - 1] = share;
        }
        SubtreeCost own{{}, left.leaves + right.leaves};
        const double as_node = area * kNodeStepCost + node_memory + shared[usable - 1];
        const double as_leaf = plan.triangles[i] <= largest_leaf
                                   ? (area * kBlockTestCost + block_memory) * blocks_of(plan.triangles[i])
                                   : std::numeric_limits<double>::infinity();
        plan.split[i] = left_share[usable - 1];
        plan.decision[i][0] = as_leaf <= as_node ? kAsLeaf : kAsNode;
        own.cost[0] = std::min(as_leaf, as_node);
        for (std::size_t s = 2; s <= Width; ++s) {
            const bool fewer = s > usable || own.cost[s - 2] <= shared[s - 1];
            plan.decision[i][s - 1] = fewer ? kFewerSlots : left_share[s - 1];
            own.cost[s - 1] = fewer ? own.cost[s - 2] : shared[s - 1];
        }
        pending.push_back(own);
    }
    return plan;
}

/// A wide node to fill: its index and the binary nodes that become its children.
template <std::size_t Width>
struct PlannedNode {
    std::uint32_t index;
    std::uint32_t depth;
    std::uint32_t children[Width];
    std::uint32_t child_count;
};

/// A leaf to fill: where its triangles' leaf-order positions start in the list of them, how many
/// there are, its first block.
struct PlannedLeaf {
    std::uint32_t first_source, triangle_count, first_block;
};

/// Appends to `sources` the leaf-order positions of the triangles a wide leaf holds: those of the
/// binary subtree's span [first, first + spanned) that have area, each id once (a triangle cut by
/// spatial splits may reach one wide leaf through several binary leaves); returns how many.
std::uint32_t append_leaf_sources(std::uint32_t first, std::uint32_t spanned, std::span<const char> with_area,
                                  std::span<const TriangleId> ids, std::vector<std::uint32_t>& sources) {
    const std::size_t begin = sources.size();
    for (std::uint32_t p = first; p != first + spanned; ++p) {
        const auto same_id = [&](std::uint32_t q) { return ids[q] == ids[p]; };
        if (with_area[p] && std::none_of(sources.begin() + std::ptrdiff_t(begin), sources.end(), same_id))
            sources.push_back(p);
    }
    return std::uint32_t(sources.size() - begin);
}

/// The wide node made of binary node b: its Width slots shared between b's children as planned.
template <std::size_t Width>
PlannedNode<Width> plan_node(const CollapsePlan<Width>& plan, std::span<const BvhNode> nodes, std::uint32_t b,
                             std::uint32_t index, std::uint32_t depth) {
    PlannedNode<Width> node{index, depth, {}, 0};
    plan.collect(nodes, b + 1, plan.split[b], node.children, node.child_count);
    plan.collect(nodes, nodes[b].right_child(), Width - plan.split[b], node.children, node.child_count);
    return node;
}

/// The first leaf-order triangle of a binary subtree: its leftmost leaf's.
std::uint32_t first_triangle_of(std::span<const BvhNode> nodes, std::uint32_t i) {
    while (!nodes[i].is_leaf()) ++i;  // the left child follows its parent
    return nodes[i].first_triangle();
}

}  // namespace

template <std::size_t Width, std::size_t BlockSize>
WideArrays<Width, BlockSize> collapse_to_wide(std::span<const BvhNode> nodes, const Mesh& mesh,
                                              std::span<const TriangleId> ids, std::uint32_t leaf_limit) {
    static_assert(Width >= 2 && Width <= 16 && BlockSize >= 1);
    WideArrays<Width, BlockSize> out;
    if (nodes.empty()) return out;
    const std::vector<char> with_area = triangles_with_area(mesh, ids);
    const CollapsePlan<Width> plan = plan_collapse<Width, BlockSize>(nodes, with_area, leaf_limit);
    const double root_area = surface_area_in_double(nodes[0].bounds);
    const auto weight = [&](std::uint32_t binary) {
        return root_area > 0.0 ? surface_area_in_double(nodes[binary].bounds) / root_area : 1.0;
    };

    // Plan serially (a few operations a wide node), children of a node numbered side by side.
    // Taking the planned nodes in order as a queue numbers them breadth-first, level by level:
    // the packet switch bounds the level of a node by its offset (nodes_above_level).
    std::vector<PlannedNode<Width>> planned;
    std::vector<PlannedLeaf> leaves;
    std::vector<std::uint32_t> leaf_sources;  // the leaves' triangles, leaf by leaf
    std::vector<ChildRef> refs(Width, ChildRef::empty());  // per planned node, Width slots
    // Reserved at their bounds (a wide node or leaf per binary node at most, each triangle once):
    // growing them copied them into fresh memory over and over. Untouched capacity costs nothing.
    const std::size_t binary_leaves = (nodes.size() + 1) / 2;
    planned.reserve(binary_leaves);
    leaves.reserve(binary_leaves);
    leaf_sources.reserve(ids.size());
    refs.reserve(binary_leaves * Width);
    std::uint32_t block_count = 0;
    // The root: a binary leaf (or a root that is one wide leaf) becomes the single child of node 0.
    if (plan.is_leaf(0)) {
        planned.push_back({0, 0, {0}, 1});
    } else {
        planned.push_back(plan_node(plan, nodes, 0, 0, 0));
    }
    out.sah_cost += weight(0) * kNodeStepCost;
    for (std::size_t next = 0; next < planned.size(); ++next) {
        const PlannedNode<Width> node = planned[next];  // a copy: planning its children grows `planned`
        out.child_slots_used += node.child_count;
        for (std::uint32_t k = 0; k < node.child_count; ++k) {
            const std::uint32_t b = node.children[k];
            if (plan.is_leaf(b)) {
                const auto first_source = std::uint32_t(leaf_sources.size());
                const std::uint32_t count =
                    append_leaf_sources(first_triangle_of(nodes, b), plan.spanned[b], with_area, ids, leaf_sources);
                if (block_count > ChildRef::kMaxFirstBlock)
                    throw std::length_error("wide BVH: more than " + std::to_string(ChildRef::kMaxFirstBlock) +
                                            " triangle blocks");
                refs[next * Width + k] = ChildRef::leaf(block_count, count);
                leaves.push_back({first_source, count, block_count});
                out.references += count;
                const std::uint32_t blocks = (count + BlockSize - 1) / BlockSize;
                block_count += blocks;
                out.sah_cost += weight(b) * kBlockTestCost * double(blocks);
                out.max_depth = std::max<std::size_t>(out.max_depth, node.depth + 1);
                out.max_leaf_triangles = std::max<std::size_t>(out.max_leaf_triangles, count);
            } else {
                const auto index = std::uint32_t(planned.size());
                if (std::uint64_t(index) * sizeof(WideNode<Width>) > ChildRef::kMaxNodeOffset)
                    throw std::length_error("wide BVH: more than " +
                                            std::to_string(ChildRef::kMaxNodeOffset / sizeof(WideNode<Width>)) +
                                            " nodes");
                refs[next * Width + k] = ChildRef::node_at(std::uint32_t(index * sizeof(WideNode<Width>)));
                const PlannedNode<Width> child = plan_node(plan, nodes, b, index, node.depth + 1);
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
    // Leaf order jumps about the mesh, and a triangle's corners lie at the end of a chain of
    // loads: its id, its index triple, then each corner's x, y and z. Waiting on that chain
    // triangle by triangle took a third of the collapse's time (perf), so each link is asked for
    // ahead of its use: the index triple kIndicesAhead triangles on, the corners kCornersAhead on
    // (their triple asked for before). Gallery's blocks took 14 ms instead of 25.
    constexpr std::size_t kIndicesAhead = 64, kCornersAhead = 32;
    const auto prefetch_ahead = [&](std::size_t position) {
        if (position + kIndicesAhead < leaf_sources.size())
            prefetch_line(&mesh.triangles[ids[leaf_sources[position + kIndicesAhead]]]);
        if (position + kCornersAhead < leaf_sources.size())
            prefetch_corners(mesh, mesh.triangles[ids[leaf_sources[position + kCornersAhead]]]);
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 1024), [&](const auto& range) {
        for (std::size_t l = range.begin(); l != range.end(); ++l) {
            const PlannedLeaf& leaf = leaves[l];
            for (std::uint32_t k = 0; k < leaf.triangle_count; ++k) prefetch_ahead(leaf.first_source + k);
            for (std::uint32_t k = 0; k < (leaf.triangle_count + BlockSize - 1) / BlockSize * BlockSize; ++k) {
                // Past the leaf's last triangle, the padding repeats it.
                const std::uint32_t source = leaf_sources[leaf.first_source + std::min(k, leaf.triangle_count - 1)];
                TriangleBlock<BlockSize>& block = out.blocks[leaf.first_block + k / BlockSize];
                const std::size_t lane = k % BlockSize;
                const Triangle tri = triangle_of(mesh, ids[source]);
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

template WideArrays<4, 4> collapse_to_wide<4, 4>(std::span<const BvhNode>, const Mesh&, std::span<const TriangleId>,
                                                 std::uint32_t);
template WideArrays<8, 4> collapse_to_wide<8, 4>(std::span<const BvhNode>, const Mesh&, std::span<const TriangleId>,
                                                 std::uint32_t);
template WideArrays<16, 4> collapse_to_wide<16, 4>(std::span<const BvhNode>, const Mesh&, std::span<const TriangleId>,
                                                   std::uint32_t);

}  // namespace trident::bvh
