#pragma once
// How a BVH is built: which builder, the SAH cost model and its limits.
#include <cstdint>

namespace trident {

enum class BvhBuilder {
    binned_sah,  // SAH at the boundaries of centroid bins (Wald 2007): the fast default
    sweep_sah,   // SAH at every plane between sorted centroids, all three axes: the quality reference
    spatial_sah,  // binned SAH with spatial splits (Stich et al. 2009): the higher-quality build
};

const char* to_string(BvhBuilder builder);

struct BvhOptions {
    static constexpr int kMinBins = 8, kMaxBins = 64, kMaxLargeNodeBins = 256;
    /// Nodes with at least this many triangles are binned with large_node_bin_count bins.
    static constexpr std::uint32_t kLargeNodeMin = 1u << 14;
    static constexpr int kMaxLeafSizeLimit = 255;

    BvhBuilder builder = BvhBuilder::binned_sah;
    /// Bins per axis, in [kMinBins, kMaxBins]; small nodes use 4 + count / 4 when that is fewer.
    int bin_count = 32;
    /// Bins per axis for the few nodes of at least kLargeNodeMin triangles, in [bin_count,
    /// kMaxLargeNodeBins]. Near the root, bin boundaries that miss the gaps between clusters of
    /// geometry cost SAH in every node below. With the refined splits of the nodes below
    /// (BinnedSahSplitter::kRefineMin), 128 keep every study scene within 2.1% of the full sweep;
    /// 64 left Room 4.6% behind, and 256 cost 10% more build time for no better tree.
    int large_node_bin_count = 128;
    /// Search every axis; false searches only the axis of largest centroid extent (the study).
    /// The sweep builder always searches all three.
    bool all_axes = true;
    /// SAH costs of one traversal step and one triangle test.
    float traversal_cost = 1.0f;
    float intersection_cost = 1.0f;
    /// A node this large is split even when SAH prefers a leaf (median split if SAH finds none).
    int max_leaf_size = 8;
    /// spatial_sah: the references it may add by cutting triangles, as a share of the triangles,
    /// in [0, kMaxSpatialSplitBudget] (0: object splits only).
    float spatial_split_budget = 0.5f;
    static constexpr float kMaxSpatialSplitBudget = 4.0f;
    /// Children per node of AccelKind::bvh's tree: 2 (the binary tree), 4 or 8 (the wide BVH,
    /// wide_bvh.h, built by collapsing the binary one). 8 is the fastest on every AVX2 and
    /// AVX-512 machine measured (bench/experiments/bvh_traversal.md).
    int width = 8;

    /// The reference study's setting: traversal cost 1/4, intersection cost 1, one split axis.
    static BvhOptions study();

    /// Throws std::invalid_argument naming the first field out of range.
    void validate() const;
};

}  // namespace trident
