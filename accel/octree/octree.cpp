#include "accel/octree/octree.h"

#include <chrono>

namespace trident {

Octree Octree::build(const Mesh& mesh, const OctreeOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    Octree out;
    OctreeLayout layout = build_octree_layout(gather_triangles(mesh), options);
    out.nodes_ = std::move(layout.nodes);
    out.triangle_indices_ = std::move(layout.triangle_indices);
    out.triangles_ = std::move(layout.triangles);
    out.triangle_ids_ = std::move(layout.triangle_ids);
    out.cube_ = layout.cube;
    out.max_depth_ = layout.max_depth;
    out.warning_ = std::move(layout.warning);

    const OctreeBuildTotals& totals = layout.totals;
    const bool empty_root = out.nodes_[0].is_leaf() && out.nodes_[0].triangle_count() == 0;
    AccelStats& stats = out.stats_;
    stats.structure = "octree";
    stats.triangles = mesh.triangle_count();
    stats.nodes = out.nodes_.size();
    stats.leaves = totals.leaves;
    stats.empty_leaves = totals.empty_children + (empty_root ? 1 : 0);  // empty children are not stored
    stats.max_depth = totals.depth;
    stats.references = totals.references;
    stats.max_leaf_size = totals.max_leaf_size;
    const std::size_t filled_leaves = totals.leaves - (empty_root ? 1 : 0);
    stats.mean_leaf_size = filled_leaves ? double(totals.references) / double(filled_leaves) : 0.0;
    stats.sah_cost = totals.sah_cost;
    stats.bytes = out.nodes_.size() * sizeof(OctreeNode) + out.triangle_indices_.size() * sizeof(std::uint32_t) +
                  out.triangles_.size() * (sizeof(Triangle) + sizeof(TriangleId));
    stats.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return out;
}

}  // namespace trident
