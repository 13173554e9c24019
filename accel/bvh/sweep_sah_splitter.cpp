#include "accel/bvh/sweep_sah_splitter.h"

#include <tbb/parallel_invoke.h>
#include <tbb/parallel_sort.h>

#include <numeric>

namespace trident::bvh {

namespace {

/// Nodes at least this large sweep their three axes in parallel.
constexpr std::uint32_t kParallelSweepMin = 1u << 14;

}  // namespace

SweepSahSplitter::SweepSahSplitter(std::span<const PrimitiveRef> refs, const BvhOptions& options)
    : refs_(refs), options_(options), scratch_(refs.size()), goes_left_(refs.size()) {
    auto sort_axis = [&](int axis) {
        std::vector<std::uint32_t>& ids = sorted_[axis];
        ids.resize(refs.size());
        std::iota(ids.begin(), ids.end(), 0u);
        tbb::parallel_sort(ids.begin(), ids.end(), [&](std::uint32_t a, std::uint32_t b) {
            const float ca = refs_[a].centroid(axis), cb = refs_[b].centroid(axis);
            return ca < cb || (ca == cb && a < b);
        });
        right_area_[axis].resize(refs.size());
    };
    tbb::parallel_invoke([&] { sort_axis(0); }, [&] { sort_axis(1); }, [&] { sort_axis(2); });
}

void SweepSahSplitter::sweep_axis(const BuildRange& range, int axis, Split& best) {
    const std::uint32_t* ids = sorted_[axis].data();
    float* right_area = right_area_[axis].data();
    const float node_area = range.bounds.surface_area();
    Aabb box;
    for (std::uint32_t i = range.end - 1; i > range.begin; --i) {
        box.extend(refs_[ids[i]].bounds());
        right_area[i] = box.surface_area();
    }
    box = Aabb{};
    for (std::uint32_t i = range.begin; i + 1 < range.end; ++i) {
        box.extend(refs_[ids[i]].bounds());
        // Only positions a plane can make: references with equal centroids stay on one side.
        if (refs_[ids[i]].centroid(axis) == refs_[ids[i + 1]].centroid(axis)) continue;
        const std::uint32_t left_count = i + 1 - range.begin, right_count = range.count() - left_count;
        const float cost = options_.traversal_cost * node_area +
                           options_.intersection_cost *
                               (box.surface_area() * float(left_count) + right_area[i + 1] * float(right_count));
        if (cost < best.cost) best = {axis, left_count, cost};
    }
}

SweepSahSplitter::Split SweepSahSplitter::find_sah_split(const BuildRange& range) {
    Split per_axis[3];
    if (range.count() >= kParallelSweepMin) {
        tbb::parallel_invoke([&] { sweep_axis(range, 0, per_axis[0]); }, [&] { sweep_axis(range, 1, per_axis[1]); },
                             [&] { sweep_axis(range, 2, per_axis[2]); });
    } else {
        for (int axis = 0; axis < 3; ++axis) sweep_axis(range, axis, per_axis[axis]);
    }
    Split best;
    for (const Split& s : per_axis)
        if (s.cost < best.cost) best = s;  // ties keep the lower axis, whatever ran in parallel
    return best;
}

ChildRanges SweepSahSplitter::partition(const BuildRange& range, const Split& split) {
    const std::uint32_t mid = range.begin + split.left_count;
    const std::vector<std::uint32_t>& by_split_axis = sorted_[split.axis];
    for (std::uint32_t i = range.begin; i != range.end; ++i) goes_left_[by_split_axis[i]] = i < mid;
    for (int axis = 0; axis < 3; ++axis) {
        if (axis == split.axis) continue;
        std::vector<std::uint32_t>& ids = sorted_[axis];
        std::uint32_t left = range.begin, right = mid;
        for (std::uint32_t i = range.begin; i != range.end; ++i)
            scratch_[goes_left_[ids[i]] ? left++ : right++] = ids[i];
        std::copy(scratch_.begin() + range.begin, scratch_.begin() + range.end, ids.begin() + range.begin);
    }
    ChildRanges out{{range.begin, mid, {}, {}}, {mid, range.end, {}, {}}, split.axis};
    for (BuildRange* side : {&out.left, &out.right})
        for (std::uint32_t i = side->begin; i != side->end; ++i) {
            const PrimitiveRef& ref = refs_[by_split_axis[i]];
            side->bounds.extend(ref.bounds());
            side->centroid_bounds.extend(ref.centroid());
        }
    return out;
}

ChildRanges SweepSahSplitter::partition_median(const BuildRange& range) {
    return partition(range, {range.centroid_bounds.largest_axis(), range.count() / 2, kInfinity});
}

}  // namespace trident::bvh
