#include "accel/accel_stats.h"

#include <fmt/format.h>

namespace trident {

std::string AccelStats::to_line() const {
    return fmt::format(
        "{}: {} triangles, build {:.1f} ms ({:.2f} Mtri/s), {} nodes, {} leaves ({} empty), depth {}, "
        "leaf size mean {:.2f} max {}, {:.2f} refs/tri, SAH cost {:.2f}, {:.2f} MiB ({:.1f} B/tri)",
        structure, triangles, build_ms, build_ms > 0 ? double(triangles) / build_ms / 1000.0 : 0.0, nodes, leaves,
        empty_leaves, max_depth, mean_leaf_size, max_leaf_size, references_per_triangle(), sah_cost,
        double(bytes) / (1024.0 * 1024.0), bytes_per_triangle()) +
           (mean_children > 0.0
                ? fmt::format(", {:.2f} children/node, blocks {:.1f}% full", mean_children, 100.0 * block_fill)
                : std::string()) +
           (builder.empty() ? std::string() : ", builder " + builder);
}

}  // namespace trident
