#include "accel/kdtree/kdtree.h"

#include <algorithm>
#include <chrono>

#include "accel/kdtree/kd_build.h"

namespace trident {

namespace {

/// Walks the finished tree: counts, depth and its SAH cost (the builder's model without the
/// empty bonus: traversal cost per interior node and intersection cost per reference, each
/// weighted by the cell's surface area relative to the root's).
void describe_tree(const KdTree& tree, const KdTreeOptions& options, AccelStats& stats) {
    const std::span<const KdNode> nodes = tree.nodes();
    stats.nodes = nodes.size();
    stats.references = tree.leaf_triangles().size();
    if (nodes.empty()) return;
    const double root_area = tree.bounds().surface_area();
    struct Item {
        std::uint32_t node;
        Aabb cell;
        std::size_t depth;
    };
    std::vector<Item> stack{{0, tree.bounds(), 0}};
    double weighted_cost = 0.0;
    while (!stack.empty()) {
        const Item item = stack.back();
        stack.pop_back();
        const KdNode& node = nodes[item.node];
        const double area = item.cell.surface_area();
        stats.max_depth = std::max(stats.max_depth, item.depth);
        if (node.is_leaf()) {
            ++stats.leaves;
            stats.empty_leaves += node.triangle_count() == 0;
            stats.max_leaf_size = std::max<std::size_t>(stats.max_leaf_size, node.triangle_count());
            weighted_cost += double(options.intersection_cost) * node.triangle_count() * area;
            continue;
        }
        weighted_cost += double(options.traversal_cost) * area;
        Item below{node.below_child(), item.cell, item.depth + 1}, above{node.above_child(), item.cell, item.depth + 1};
        below.cell.hi[node.axis()] = node.split();
        above.cell.lo[node.axis()] = node.split();
        stack.push_back(above);
        stack.push_back(below);
    }
    const std::size_t filled = stats.leaves - stats.empty_leaves;
    stats.mean_leaf_size = filled ? double(stats.references) / double(filled) : 0.0;
    stats.sah_cost = root_area > 0.0 ? weighted_cost / root_area : 0.0;
}

}  // namespace

KdTree KdTree::build(const Mesh& mesh, const KdTreeOptions& options) {
    options.validate();
    const auto start = std::chrono::steady_clock::now();
    KdTree out;
    KdBuildResult built = build_kdtree(gather_triangles(mesh), options);
    out.nodes_ = std::move(built.nodes);
    out.leaf_triangles_ = std::move(built.leaf_triangles);
    out.triangles_ = std::move(built.triangles);
    out.triangle_ids_ = std::move(built.triangle_ids);
    out.bounds_ = built.bounds;
    out.stats_.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

    out.stats_.structure = "kdtree";
    out.stats_.triangles = mesh.triangle_count();
    out.stats_.bytes = out.nodes_.size() * sizeof(KdNode) + out.leaf_triangles_.size() * sizeof(TriangleId) +
                       out.triangles_.size() * (sizeof(Triangle) + sizeof(TriangleId));
    describe_tree(out, options, out.stats_);
    return out;
}

}  // namespace trident
