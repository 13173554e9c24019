// The driver of the kd-tree build (kd_builder.h): the root's events, the recursion down the tree
// with its subtrees as tasks, and the subtrees' layout in the final depth-first array.
#include "accel/kdtree/kd_build.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "accel/kdtree/kd_builder.h"
#include "accel/kdtree/radix_sort.h"
#include "core/morton.h"

namespace trident {

namespace kd {

namespace {

/// Events hold a node-local triangle index in 30 bits.
constexpr std::size_t kMaxTriangles = std::size_t(1) << 30;

/// Events on `axis` for each flat-axes entry: 1 where the bounds are flat, 2 elsewhere.
std::size_t event_count(std::span<const std::uint8_t> flat_axes, int axis) {
    std::size_t flat = 0;
    for (const std::uint8_t f : flat_axes) flat += (f >> axis) & 1u;
    return 2 * flat_axes.size() - flat;
}

}  // namespace

KdBuildResult SahBuilder::run() {
    KdBuildResult result;
    ThreadScratch& scratch = scratch_.local();
    const NodeWork root = make_root(scratch, result.bounds, result.triangle_ids);
    if (root.size() == 0) return result;
    max_depth_ = options_.depth_limit(root.size());
    Subtree tree;
    build_subtree(root, tree, 0, 0, scratch);
    // Reserved at their final sizes: growing these (tens of MiB) copies and faults them in again.
    std::array<std::size_t, 2> sizes{1, 0};
    count_emitted(tree, sizes);
    result.nodes.reserve(sizes[0]);
    result.leaf_triangles.reserve(sizes[1]);
    result.nodes.push_back(kPlaceholder);
    emit(tree, 0, result);
    result.triangles = std::move(triangles_);
    return result;
}

NodeWork SahBuilder::make_root(ThreadScratch& scratch, Aabb& bounds, std::vector<TriangleId>& order) {
    std::vector<Aabb> file_bounds;
    file_bounds.reserve(file_triangles_.size());
    std::size_t finite = 0;
    for (std::size_t i = 0; i < file_triangles_.size(); ++i) {
        const Triangle& t = file_triangles_[i];
        file_bounds.push_back(t.bounds());
        if (is_finite(t.a) && is_finite(t.b) && is_finite(t.c)) {
            bounds.extend(file_bounds[i]);
            ++finite;
        }
    }
    if (finite > kMaxTriangles)
        throw std::length_error("kd-tree: " + std::to_string(finite) + " triangles exceed the " +
                                std::to_string(kMaxTriangles) + " an event can index (30 bits)");
    NodeWork root{
        bounds, scratch.kept.allocate<std::uint32_t>(finite), scratch.kept.allocate<std::uint8_t>(finite), {}};
    const ScratchArena::Mark temp_mark = scratch.temp.mark();
    // The triangles in Morton order of their centres: the splitting passes look up
    // per-triangle data by the index of each event, and the traversals read the triangles of
    // a leaf, and both then touch memory near in the array for triangles near in space. The
    // scanned meshes' files are far from that order (bench/experiments/kdtree.md measures what it
    // gives). The tree does not depend on this order.
    const std::span<std::uint64_t> coded = scratch.temp.allocate<std::uint64_t>(finite);
    const Vec3f extent = max(bounds.extent(), Vec3f(std::numeric_limits<float>::min()));
    const Vec3f scale{1023.0f / extent.x, 1023.0f / extent.y, 1023.0f / extent.z};
    std::size_t n = 0;
    for (std::size_t i = 0; i < file_triangles_.size(); ++i) {
        const Triangle& t = file_triangles_[i];
        if (!(is_finite(t.a) && is_finite(t.b) && is_finite(t.c))) continue;
        const Vec3f cell = (file_bounds[i].center() - bounds.lo) * scale;
        const std::uint32_t code = morton_code(std::uint32_t(cell.x), std::uint32_t(cell.y), std::uint32_t(cell.z));
        coded[n++] = std::uint64_t(code) << 32 | i;
    }
    radix_sort(coded, scratch.temp.allocate<std::uint64_t>(n), [](std::uint64_t c) { return std::uint32_t(c >> 32); });
    order.reserve(n);
    triangles_.reserve(n);
    bounds_.reserve(n);
    for (std::size_t j = 0; j < n; ++j) {
        const auto id = std::uint32_t(coded[j]);
        order.push_back(id);
        triangles_.push_back(file_triangles_[id]);
        bounds_.push_back(file_bounds[id]);
        root.prims[j] = std::uint32_t(j);
        root.flat_axes[j] = flat_axes_of(bounds_[j]);
    }
    std::array<std::size_t, 3> sizes{};
    for (int axis = 0; axis < 3; ++axis) {
        sizes[axis] = event_count(root.flat_axes, axis);
        root.events[axis] = scratch.kept.allocate<Event>(sizes[axis]);
    }
    const bool parallel = parallel_axes(n);
    const std::span<Event> sort_space = scratch.temp.allocate<Event>((parallel ? 3 : 1) * 2 * n);
    for_each_axis(parallel, [&](int axis) {
        const std::size_t flat = 2 * n - sizes[axis];
        write_events(
            n, [&](std::size_t i) -> const Aabb& { return bounds_[root.prims[i]]; }, axis, 0, flat, root.events[axis]);
        sort_events(root.events[axis], sort_space.subspan(parallel ? 2 * n * std::size_t(axis) : 0));
    });
    scratch.temp.release(temp_mark);
    return root;
}
void SahBuilder::build_subtree(const NodeWork& node, Subtree& out, int depth, int bad_refines, ThreadScratch& scratch) {
    out.nodes.push_back(kPlaceholder);
    build_node(node, out, 0, depth, bad_refines, scratch);
}

void SahBuilder::build_node(const NodeWork& node, Subtree& out, std::size_t slot, int depth, int bad_refines,
                            ThreadScratch& scratch) {
    Split split;
    if (node.size() > options_.leaf_triangles && depth < max_depth_) {
        if (node.size() <= options_.small_node_triangles) {
            build_small(small_node_of(node), out, slot, depth, bad_refines);
            return;
        }
        split = judged(find_split(node), node.size(), bad_refines);
    }
    if (!split.found()) {
        make_leaf(node.prims, out, slot);
        return;
    }

    const ScratchArena::Mark mark = scratch.kept.mark();
    const auto [below, above] = split_node(node, split, depth + 1 < max_depth_, scratch);
    if (node.size() >= options_.parallel_triangles) {
        // Children as tasks, into subtrees of their own; emit() lays them out as the
        // sequential branch would have. Children never outnumber their parent, so a node
        // this large is the root of its subtree.
        out.nodes[slot] = KdNode::interior(split.axis, split.position, 1);  // index set by emit()
        for (auto& child : out.children) child = std::make_unique<Subtree>();
        tbb::parallel_invoke([&] { build_subtree(below, *out.children[0], depth + 1, bad_refines, scratch_.local()); },
                             [&] { build_subtree(above, *out.children[1], depth + 1, bad_refines, scratch_.local()); });
    } else {
        const std::size_t first_child = out.nodes.size();
        out.nodes[slot] = KdNode::interior(split.axis, split.position, first_child);
        out.nodes.push_back(kPlaceholder);
        out.nodes.push_back(kPlaceholder);
        build_node(below, out, first_child, depth + 1, bad_refines, scratch);
        build_node(above, out, first_child + 1, depth + 1, bad_refines, scratch);
    }
    scratch.kept.release(mark);
}

Split SahBuilder::judged(Split split, std::size_t size, int& bad_refines) const {
    const double leaf_cost = double(options_.intersection_cost) * double(size);
    if (split.found() && split.cost > leaf_cost) {
        ++bad_refines;
        if (bad_refines >= options_.max_bad_refines || (split.cost > 4.0 * leaf_cost && size < 16)) return {};
    } else {
        bad_refines = 0;
    }
    return split;
}

void SahBuilder::make_leaf(std::span<const std::uint32_t> prims, Subtree& out, std::size_t slot) {
    const std::size_t offset = out.leaf_triangles.size();
    out.nodes[slot] = KdNode::leaf(std::uint32_t(prims.size()), offset);
    out.leaf_triangles.insert(out.leaf_triangles.end(), prims.begin(), prims.end());
    if (prims.size() > 1) std::sort(out.leaf_triangles.begin() + std::ptrdiff_t(offset), out.leaf_triangles.end());
}

void SahBuilder::count_emitted(const Subtree& tree, std::array<std::size_t, 2>& sizes) {
    if (tree.children[0]) {
        sizes[0] += 2;
        for (const auto& child : tree.children) count_emitted(*child, sizes);
        return;
    }
    sizes[0] += tree.nodes.size() - 1;
    sizes[1] += tree.leaf_triangles.size();
}

void SahBuilder::emit(const Subtree& tree, std::size_t slot, KdBuildResult& out) {
    if (tree.children[0]) {
        const KdNode& root = tree.nodes[0];
        const std::size_t first_child = out.nodes.size();
        out.nodes[slot] =
            KdNode::interior(root.axis(), root.split(), first_child, tree.children[0]->nodes[0].is_empty_leaf(),
                             tree.children[1]->nodes[0].is_empty_leaf());
        out.nodes.push_back(kPlaceholder);
        out.nodes.push_back(kPlaceholder);
        emit(*tree.children[0], first_child, out);
        emit(*tree.children[1], first_child + 1, out);
        return;
    }
    const std::size_t node_base = out.nodes.size() - 1;  // tree.nodes[j], j >= 1, lands at node_base + j
    const std::size_t triangle_base = out.leaf_triangles.size();
    auto moved = [&](const KdNode& n) {
        return n.is_leaf() ? KdNode::leaf(n.triangle_count(), triangle_base + n.triangle_offset())
                           : KdNode::interior(n.axis(), n.split(), node_base + n.below_child(),
                                              tree.nodes[n.below_child()].is_empty_leaf(),
                                              tree.nodes[n.above_child()].is_empty_leaf());
    };
    out.nodes[slot] = moved(tree.nodes[0]);
    for (std::size_t j = 1; j < tree.nodes.size(); ++j) out.nodes.push_back(moved(tree.nodes[j]));
    out.leaf_triangles.insert(out.leaf_triangles.end(), tree.leaf_triangles.begin(), tree.leaf_triangles.end());
}

}  // namespace kd

KdBuildResult build_kdtree(std::span<const Triangle> triangles, const KdTreeOptions& options) {
    return kd::SahBuilder(triangles, options).run();
}

}  // namespace trident
