#pragma once
// How a BVH is built: which builder, the SAH cost model and its limits.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace trident {

enum class BvhBuilder {
    automatic,   // the default: the wide BVH picks spatial_sah or binned_sah per mesh (builder_choice.h),
                 // the binary BVH (the study's) binned_sah
    binned_sah,  // SAH at the boundaries of centroid bins (Wald 2007): the fast build
    sweep_sah,   // SAH at every plane between sorted centroids, all three axes: the quality reference
    spatial_sah,  // binned SAH with spatial splits (Stich et al. 2009): the higher-quality build
};

const char* to_string(BvhBuilder builder);

/// The builders by their command-line and Python names: auto, binned, sweep, spatial.
struct BvhBuilderName {
    const char* name;
    BvhBuilder builder;
};
inline constexpr BvhBuilderName kBvhBuilderNames[] = {{"auto", BvhBuilder::automatic},
                                                      {"binned", BvhBuilder::binned_sah},
                                                      {"sweep", BvhBuilder::sweep_sah},
                                                      {"spatial", BvhBuilder::spatial_sah}};
/// The builder of a name in kBvhBuilderNames; throws std::invalid_argument for any other.
BvhBuilder parse_bvh_builder(std::string_view name);
/// kBvhBuilderNames' names, for option checks and messages.
std::vector<std::string> bvh_builder_names();

/// The wide BVH's fastest node width where this process runs (under TRIDENT_ISA's cap): 16
/// children where its kernels have 8 or 16 lanes (AVX2, AVX-512), whose box tests take a 16-wide
/// node in two vector steps or one, and a ray then passes three or four fewer nodes between the
/// root and a leaf; 8 where they have SSE4.2's 4 lanes only, whose four steps a node made 16
/// children no faster (bench/experiments/bvh-traversal.md).
int fastest_wide_width();

struct BvhOptions {
    static constexpr int kMinBins = 8, kMaxBins = 64, kMaxLargeNodeBins = 256;
    /// Nodes with at least this many triangles are binned with large_node_bin_count bins.
    static constexpr std::uint32_t kLargeNodeMin = 1u << 14;
    static constexpr int kMaxLeafSizeLimit = 255;

    BvhBuilder builder = BvhBuilder::automatic;
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
    /// Triangles a leaf tests in one step: 1 for the binary tree, the block size when the tree is
    /// collapsed into the wide BVH's blocks of triangles (wide_bvh.h). See fits_one_block().
    int leaf_block_size = 1;
    /// spatial_sah: the references it may add by cutting triangles, as a share of the triangles,
    /// in [0, kMaxSpatialSplitBudget] (0: object splits only).
    float spatial_split_budget = 0.5f;
    static constexpr float kMaxSpatialSplitBudget = 4.0f;
    /// Children per node of AccelKind::bvh's tree: 2 (the binary tree), 4, 8 or 16 (the wide BVH,
    /// wide_bvh.h, built by collapsing the binary one); by default the fastest for this CPU.
    int width = fastest_wide_width();

    /// Whether a node of `count` triangles fits one leaf block. Such a node's split is judged by
    /// split_beats_block(), the collapse's cost, instead of the binary tree's SAH.
    bool fits_one_block(std::uint32_t count) const { return count <= std::uint32_t(leaf_block_size); }

    /// The share of a one-block node's area that its children's areas must stay under for a split.
    /// At 1 (the bare cost comparison) the trees were those of the binary SAH, blocks 72-77% full
    /// and 63.8-67.8 bytes a triangle on the study scenes; never splitting such nodes filled blocks
    /// to 79-84% (59.6-63.7 bytes) but slowed Sponza's rays by up to 9%, where a few large
    /// triangles far apart share a node. 0.85 kept Sponza's and Gallery's rays within noise of the
    /// old trees and gave 60.3-64.6 bytes a triangle, before the collapse weighed memory too
    /// (kBlockMemoryCost in wide_collapse.cpp; bench/experiments/bvh-build.md).
    static constexpr float kBlockSplitShare = 0.85f;

    /// For a node that fits one block: whether splitting it pays in the wide tree. As a leaf it is
    /// one block test over its area; split, its children become two leaves in two slots of the wide
    /// node above (the collapse folds the binary node away), one block test each over its own area,
    /// and the slot the split takes is one another subtree no longer has (kBlockSplitShare). The
    /// binary SAH instead charges a node step and a test per triangle, so it split nearly every
    /// such node, and the collapse gathered many of them into one block again.
    static bool split_beats_block(float left_area, float right_area, float area) {
        return left_area + right_area < kBlockSplitShare * area;
    }

    /// The reference study's setting: traversal cost 1/4, intersection cost 1, one split axis.
    static BvhOptions study();

    /// Throws std::invalid_argument naming the first field out of range.
    void validate() const;
};

}  // namespace trident
