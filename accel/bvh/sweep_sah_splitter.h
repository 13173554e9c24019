#pragma once
// Full-sweep SAH split search: the SAH at every plane between consecutive distinct centroids on
// all three axes (MacDonald and Booth 1990; the presorted form of Wald, Boulos and Shirley,
// "Ray Tracing Deformable Scenes using Dynamic BVHs", 2007). The references are sorted once per
// axis; a split stably partitions the other two sorted lists, so every node stays O(n). Slower
// than binning and kept as the quality reference the binned builder is measured against: it
// considers exactly the partitions a centroid plane can make, which binning approximates.
#include <cstdint>
#include <span>
#include <vector>

#include "accel/bvh/build_primitives.h"
#include "accel/bvh/bvh_options.h"
#include "core/ray.h"

namespace trident::bvh {

class SweepSahSplitter {
public:
    struct Split {
        int axis = -1;
        std::uint32_t left_count = 0;  // the first left_count of the node's list sorted on axis go left
        float cost = kInfinity;        // traversal_cost * A + intersection_cost * (A_L N_L + A_R N_R)
    };

    /// `refs` in file order (refs[i].id == i); they are read, never moved.
    SweepSahSplitter(std::span<const PrimitiveRef> refs, const BvhOptions& options);

    Split find_sah_split(const BuildRange& range);
    ChildRanges partition(const BuildRange& range, const Split& split);
    /// Object median along the axis of largest centroid extent.
    ChildRanges partition_median(const BuildRange& range);

    /// File-order ids in leaf order, once the tree is built.
    std::span<const std::uint32_t> leaf_order() const { return sorted_[0]; }

private:
    void sweep_axis(const BuildRange& range, int axis, Split& best);

    std::span<const PrimitiveRef> refs_;
    const BvhOptions& options_;
    std::vector<std::uint32_t> sorted_[3];  // per axis, each node's ids sorted by centroid (ties by id)
    std::vector<float> right_area_[3];      // per axis, scratch: area of the ids from position i on
    std::vector<std::uint32_t> scratch_;
    std::vector<std::uint8_t> goes_left_;  // per id, set during a partition
};

}  // namespace trident::bvh
