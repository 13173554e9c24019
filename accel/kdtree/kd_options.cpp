#include "accel/kdtree/kd_options.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "accel/kdtree/kd_node.h"

namespace trident {

void KdTreeOptions::validate() const {
    auto fail = [](const std::string& what) { throw std::invalid_argument("kd-tree options: " + what); };
    if (!(intersection_cost > 0.0f && std::isfinite(intersection_cost))) fail("intersection_cost must be positive");
    if (!(traversal_cost >= 0.0f && std::isfinite(traversal_cost))) fail("traversal_cost must be >= 0");
    if (!(empty_bonus >= 0.0f && empty_bonus < 1.0f)) fail("empty_bonus must be in [0, 1)");
    if (max_depth >= kKdMaxDepth)
        fail("max_depth must be below " + std::to_string(kKdMaxDepth) + " (the traversal stack)");
    if (depth_offset <= -kKdMaxDepth || depth_offset >= kKdMaxDepth)
        fail("depth_offset must lie strictly between -" + std::to_string(kKdMaxDepth) + " and " +
             std::to_string(kKdMaxDepth));
    if (max_bad_refines < 1) fail("max_bad_refines must be >= 1");
    if (leaf_triangles < 1) fail("leaf_triangles must be >= 1");
    if (parallel_triangles < 2) fail("parallel_triangles must be >= 2");
    if (small_node_triangles > kMaxSmallNodeTriangles)
        fail("small_node_triangles must be at most " + std::to_string(kMaxSmallNodeTriangles));
}

int KdTreeOptions::depth_limit(std::size_t n) const {
    if (max_depth >= 0) return max_depth;
    const double pbrt = 8.0 + 1.3 * std::log2(double(std::max<std::size_t>(n, 1)));
    return std::clamp(int(std::lround(pbrt)) + depth_offset, 0, kKdMaxDepth - 1);
}

}  // namespace trident
