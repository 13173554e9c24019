#include "accel/bvh/wide_bvh.h"

#include <algorithm>
#include <chrono>

#include "accel/bvh/builder_choice.h"
#include "accel/bvh/bvh.h"
#include "accel/bvh/wide_collapse.h"

namespace trident {

template <std::size_t Width, std::size_t BlockSize>
WideBvh<Width, BlockSize> WideBvh<Width, BlockSize>::build(const Mesh& mesh, const BvhOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    const auto build_with = [&](BvhBuilder builder) {
        BvhOptions binary_options = options;
        binary_options.builder = builder;
        binary_options.leaf_block_size = std::min(int(BlockSize), options.max_leaf_size);
        const bvh::BinaryTree binary = bvh::build_binary_tree(mesh, binary_options);
        return bvh::collapse_to_wide<Width, BlockSize>(binary.nodes, mesh, binary.leaf_ids,
                                                       std::uint32_t(options.max_leaf_size));
    };
    BvhBuilder builder = options.builder;
    if (builder == BvhBuilder::automatic)
        builder = bvh::tries_spatial_splits(mesh) ? BvhBuilder::spatial_sah : BvhBuilder::binned_sah;
    bvh::WideArrays<Width, BlockSize> wide = build_with(builder);
    if (options.builder == BvhBuilder::automatic && builder == BvhBuilder::spatial_sah) {
        bvh::WideArrays<Width, BlockSize> binned = build_with(BvhBuilder::binned_sah);
        if (!bvh::spatial_tree_pays(wide.sah_cost, binned.sah_cost)) {
            wide = std::move(binned);
            builder = BvhBuilder::binned_sah;
        }
    }
    const double build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

    WideBvh result;
    result.options_ = options;
    result.options_.builder = builder;  // what built the tree, automatic resolved
    result.nodes_ = std::move(wide.nodes);
    result.blocks_ = std::move(wide.blocks);
    result.lane_use_end_ =
        std::uint32_t(bvh::nodes_above_level<Width>(result.nodes_, kIncoherentLaneUseLevels) * sizeof(Node));
    AccelStats& stats = result.stats_;
    stats.structure = "bvh" + std::to_string(Width);
    stats.triangles = mesh.triangle_count();
    stats.nodes = result.nodes_.size() + wide.leaves;
    stats.leaves = wide.leaves;
    stats.max_depth = wide.max_depth;
    stats.references = wide.references;  // zero-area triangles are left out
    stats.max_leaf_size = wide.max_leaf_triangles;
    stats.mean_leaf_size = wide.leaves ? double(stats.references) / double(wide.leaves) : 0.0;
    stats.sah_cost = wide.sah_cost;
    stats.bytes = result.nodes_.size() * sizeof(Node) + result.blocks_.size() * sizeof(Block);
    stats.mean_children = result.nodes_.empty() ? 0.0 : double(wide.child_slots_used) / double(result.nodes_.size());
    stats.block_fill =
        result.blocks_.empty() ? 0.0 : double(stats.references) / double(result.blocks_.size() * BlockSize);
    stats.build_ms = build_ms;
    stats.builder = to_string(builder);
    return result;
}

template class WideBvh<4, 4>;
template class WideBvh<8, 4>;
template class WideBvh<16, 4>;

}  // namespace trident
