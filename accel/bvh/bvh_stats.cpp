#include "accel/bvh/bvh_stats.h"

#include <algorithm>
#include <vector>

#include "core/mesh.h"
#include "core/ray.h"

namespace trident {

double bvh_sah_cost(std::span<const BvhNode> nodes, float traversal_cost, float intersection_cost) {
    if (nodes.empty()) return 0.0;
    const double root_area = surface_area_in_double(nodes[0].bounds);
    double cost = 0.0;
    for (const BvhNode& node : nodes) {
        const double weight = root_area > 0.0 ? surface_area_in_double(node.bounds) / root_area : 1.0;
        cost += weight * (node.is_leaf() ? double(intersection_cost) * node.triangle_count() : double(traversal_cost));
    }
    return cost;
}

AccelStats bvh_stats(std::span<const BvhNode> nodes, std::size_t triangle_count, const BvhOptions& options) {
    AccelStats stats;
    stats.structure = "bvh2";
    stats.builder = to_string(options.builder);
    stats.triangles = triangle_count;
    stats.nodes = nodes.size();
    // Depth-first order puts both children after their parent, so one forward pass gives depths.
    std::vector<std::uint8_t> depth(nodes.size(), 0);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const BvhNode& node = nodes[i];
        stats.max_depth = std::max<std::size_t>(stats.max_depth, depth[i]);
        if (node.is_leaf()) {
            ++stats.leaves;
            stats.references += node.triangle_count();
            stats.max_leaf_size = std::max<std::size_t>(stats.max_leaf_size, node.triangle_count());
        } else {
            depth[i + 1] = depth[node.right_child()] = std::uint8_t(depth[i] + 1);
        }
    }
    stats.mean_leaf_size = stats.leaves ? double(stats.references) / double(stats.leaves) : 0.0;
    stats.sah_cost = bvh_sah_cost(nodes, options.traversal_cost, options.intersection_cost);
    stats.bytes = nodes.size() * sizeof(BvhNode) + stats.references * (sizeof(Triangle) + sizeof(TriangleId));
    return stats;
}

}  // namespace trident
