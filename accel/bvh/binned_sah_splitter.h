#pragma once
// Binned SAH split search (Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies",
// IEEE RT 2007): a node's centroids are dropped into equal-width bins per axis, the SAH is
// evaluated only at bin boundaries, and the node's references are partitioned within their range.
// Large nodes are binned in parallel; the bins are unions and counts, so the result does not
// depend on how the work was divided among threads.
#include <cstdint>
#include <span>

#include "accel/bvh/build_primitives.h"
#include "accel/bvh/bvh_options.h"
#include "core/ray.h"

namespace trident::bvh {

/// Maps a centroid coordinate to its bin along one axis of a node's centroid box.
struct BinMapping {
    float origin[3];
    float scale[3];  // bins per unit length; 0 on an axis where the centroids cannot be told apart
    int count;

    BinMapping(const Aabb& centroid_bounds, int bin_count);
    bool can_split(int axis) const { return scale[axis] > 0.0f; }
    int bin(float coordinate, int axis) const {
        const int b = int((coordinate - origin[axis]) * scale[axis]);
        return b < count - 1 ? b : count - 1;
    }
};

class BinnedSahSplitter {
public:
    struct Split {
        int axis = -1;
        int last_left_bin = 0;  // bins [0, last_left_bin] go left
        std::uint32_t left_count = 0;
        float cost = kInfinity;  // traversal_cost * A + intersection_cost * (A_L N_L + A_R N_R)
        Aabb left_bounds, right_bounds;
        /// A refined split's boundary lies inside bins last_left_bin and last_left_bin + 1, after
        /// fine bin fine_last_left of the 2 * kFineBinsPerBin the two are cut into.
        bool refined = false;
        int fine_last_left = 0;
    };

    /// Nodes of kRefineMin to kRefineEnd - 1 references refine their best split: its two bins,
    /// one each side of its boundary, are cut into fine bins and the SAH evaluated at every fine
    /// boundary. Where centroids cluster far closer than a bin's width (small objects in a large
    /// room), bins alone cannot cut around the cluster: on Room that kept the binned tree 9% above
    /// the full sweep's SAH even with 256 bins a node; refining brings it within 2%, for one more
    /// pass over one axis. Refining larger nodes too gained under 0.4% SAH on the study's scenes,
    /// and their pass streams from memory.
    static constexpr std::uint32_t kRefineMin = 1024, kRefineEnd = 65536;
    /// Fine bins per bin when a split is refined.
    static constexpr int kFineBinsPerBin = 16;

    BinnedSahSplitter(std::span<PrimitiveRef> refs, const BvhOptions& options);

    /// The cheapest split at a bin boundary (or a fine one, see kRefineMin); cost is +inf when
    /// there is none.
    Split find_sah_split(const BuildRange& range) const;
    ChildRanges partition(const BuildRange& range, const Split& split);
    /// Object median along the axis of largest centroid extent (any halves when all coincide).
    ChildRanges partition_median(const BuildRange& range);

private:
    /// Two references have one split, separating them along the axis of largest centroid
    /// extent: evaluated directly, as binning them would cost far more (these are the most
    /// common nodes).
    Split split_pair(const BuildRange& range) const;
    /// Fewer bins for small nodes, as Embree does (the fixed cost of clearing and sweeping bins
    /// outweighs finer split positions there), and more for the few largest nodes, whose coarse
    /// split positions otherwise cost the most SAH (see BvhOptions::large_node_bin_count).
    int bins_for_count(std::uint32_t count) const;

    std::span<PrimitiveRef> refs_;
    const BvhOptions& options_;
};

}  // namespace trident::bvh
