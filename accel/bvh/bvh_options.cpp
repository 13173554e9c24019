#include "accel/bvh/bvh_options.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "simd/width.h"

namespace trident {

int fastest_wide_width() {
    try {
        return is_runnable(SimdWidth::w8) ? 16 : 8;
    } catch (const std::runtime_error&) {
        // A TRIDENT_ISA that names no instruction set: options are made before a command can
        // report it, and the first use of the cap after them reports it again, as one line.
        return 8;
    }
}

const char* to_string(BvhBuilder builder) {
    switch (builder) {
        case BvhBuilder::automatic: return "auto";
        case BvhBuilder::binned_sah: return "binned_sah";
        case BvhBuilder::sweep_sah: return "sweep_sah";
        case BvhBuilder::spatial_sah: return "spatial_sah";
    }
    return "unknown";
}

BvhBuilder parse_bvh_builder(std::string_view name) {
    std::string known_names;
    for (const BvhBuilderName& known : kBvhBuilderNames) {
        if (name == known.name) return known.builder;
        known_names += (known_names.empty() ? "" : ", ") + std::string(known.name);
    }
    throw std::invalid_argument("unknown BVH builder '" + std::string(name) + "' (" + known_names + ")");
}

std::vector<std::string> bvh_builder_names() {
    std::vector<std::string> names;
    for (const BvhBuilderName& known : kBvhBuilderNames) names.emplace_back(known.name);
    return names;
}

BvhOptions BvhOptions::study() {
    BvhOptions options;
    options.all_axes = false;
    options.large_node_bin_count = options.bin_count;  // one bucket count throughout
    options.traversal_cost = 0.25f;
    options.intersection_cost = 1.0f;
    return options;
}

void BvhOptions::validate() const {
    auto fail = [](const std::string& what) { throw std::invalid_argument("BvhOptions: " + what); };
    if (std::ranges::none_of(kBvhBuilderNames, [&](const BvhBuilderName& known) { return known.builder == builder; }))
        fail("unknown builder");
    if (!(spatial_split_budget >= 0.0f && spatial_split_budget <= kMaxSpatialSplitBudget))
        fail("spatial_split_budget must be in [0, " + std::to_string(kMaxSpatialSplitBudget) + "]");
    if (bin_count < kMinBins || bin_count > kMaxBins)
        fail("bin_count " + std::to_string(bin_count) + " is outside [" + std::to_string(kMinBins) + ", " +
             std::to_string(kMaxBins) + "]");
    if (large_node_bin_count < bin_count || large_node_bin_count > kMaxLargeNodeBins)
        fail("large_node_bin_count " + std::to_string(large_node_bin_count) + " is outside [bin_count, " +
             std::to_string(kMaxLargeNodeBins) + "]");
    if (!(std::isfinite(traversal_cost) && traversal_cost >= 0.0f)) fail("traversal_cost must be finite and >= 0");
    if (!(std::isfinite(intersection_cost) && intersection_cost > 0.0f))
        fail("intersection_cost must be finite and > 0");
    if (width != 2 && width != 4 && width != 8 && width != 16)
        fail("width " + std::to_string(width) + " is not 2, 4, 8 or 16");
    if (max_leaf_size < 1 || max_leaf_size > kMaxLeafSizeLimit)
        fail("max_leaf_size " + std::to_string(max_leaf_size) + " is outside [1, " + std::to_string(kMaxLeafSizeLimit) +
             "]");
    if (leaf_block_size < 1 || leaf_block_size > max_leaf_size)
        fail("leaf_block_size " + std::to_string(leaf_block_size) + " is outside [1, max_leaf_size]");
}

}  // namespace trident
