#include "accel/bvh/binned_sah_splitter.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <utility>
#include <xsimd/xsimd.hpp>

namespace trident::bvh {

namespace {

constexpr int kBinCapacity = BvhOptions::kMaxLargeNodeBins;

/// Nodes at least this large are binned in parallel.
constexpr std::uint32_t kParallelBinningMin = 1u << 15;
constexpr std::uint32_t kBinningGrain = 1u << 13;

/// Binning touches every reference on every level, so it works on whole boxes. A bin stores its
/// box as lo and -hi in eight lanes (x, y, z and a spare lane each), so that one min grows both
/// corners (Embree's binner keeps boxes the same way).
using Float4 = xsimd::make_sized_batch_t<float, 4>;
using Int4 = xsimd::make_sized_batch_t<std::int32_t, 4>;

/// `lo` with lane 3 zeroed: it holds the id's bits, which read as a denormal float for most ids,
/// and arithmetic on denormals is many times slower.
Float4 load_lo(const PrimitiveRef& ref) {
    const Float4 xyz = xsimd::bitwise_cast<Float4>(Int4{-1, -1, -1, 0});
    return Float4::load_aligned(reinterpret_cast<const float*>(&ref)) & xyz;
}
Float4 load_hi(const PrimitiveRef& ref) { return Float4::load_aligned(reinterpret_cast<const float*>(&ref) + 4); }

#if XSIMD_WITH_AVX
using Float8 = xsimd::make_sized_batch_t<float, 8>;

Float8 load_whole(const PrimitiveRef& ref) { return Float8::load_aligned(reinterpret_cast<const float*>(&ref)); }

/// A reference's box as lo, -hi, with the id's lane zeroed (see load_lo); lanes 3 and 7 are
/// never read.
Float8 load_lo_negated_hi(const PrimitiveRef& ref) {
    using Int8 = xsimd::make_sized_batch_t<std::int32_t, 8>;
    const Float8 xyz = xsimd::bitwise_cast<Float8>(Int8{-1, -1, -1, 0, -1, -1, -1, 0});
    const Float8 negate_hi = xsimd::bitwise_cast<Float8>(Int8{0, 0, 0, 0, INT32_MIN, INT32_MIN, INT32_MIN, 0});
    return (load_whole(ref) & xyz) ^ negate_hi;
}

Float8 lanes_min(const Float8& a, const Float8& b) { return xsimd::min(a, b); }
#else
/// Without AVX (the portable build's SSE4.2 baseline) the eight lanes are two halves, each
/// operation done on both: the same bits as the one 8-lane batch.
struct Float8 {
    Float4 lo, hi;

    explicit Float8(float v) : lo(v), hi(v) {}
    Float8(const Float4& lo_, const Float4& hi_) : lo(lo_), hi(hi_) {}
    static Float8 load_aligned(const float* p) { return {Float4::load_aligned(p), Float4::load_aligned(p + 4)}; }
    void store_aligned(float* p) const {
        lo.store_aligned(p);
        hi.store_aligned(p + 4);
    }
};

Float8 load_whole(const PrimitiveRef& ref) { return Float8::load_aligned(reinterpret_cast<const float*>(&ref)); }

Float8 load_lo_negated_hi(const PrimitiveRef& ref) {
    const Float4 xyz = xsimd::bitwise_cast<Float4>(Int4{-1, -1, -1, 0});
    const Float4 negate = xsimd::bitwise_cast<Float4>(Int4{INT32_MIN, INT32_MIN, INT32_MIN, 0});
    return {load_lo(ref), (load_hi(ref) & xyz) ^ negate};
}

Float8 lanes_min(const Float8& a, const Float8& b) { return {xsimd::min(a.lo, b.lo), xsimd::min(a.hi, b.hi)}; }
#endif

/// The union of a bin's boxes as lo and -hi. Plain floats keep it trivially constructible, so a
/// node clears only the bins it uses.
struct alignas(32) BinBox {
    float lo_negated_hi[8];

    void clear() { Float8(kInfinity).store_aligned(lo_negated_hi); }
    void add(const Float8& box) { lanes_min(Float8::load_aligned(lo_negated_hi), box).store_aligned(lo_negated_hi); }
    void add(const BinBox& other) { add(Float8::load_aligned(other.lo_negated_hi)); }
    Float4 lo() const { return Float4::load_aligned(lo_negated_hi); }
    Float4 negated_hi() const { return Float4::load_aligned(lo_negated_hi + 4); }
    Aabb bounds() const {
        const float* v = lo_negated_hi;
        return {{v[0], v[1], v[2]}, {-v[4], -v[5], -v[6]}};
    }
};
static_assert(sizeof(BinBox) == 32);

/// The bins of the three axes: boxes per axis, counts per bin with one lane per axis (so the
/// sweep reads the three axes' counts of a bin at once).
struct BinGrid {
    BinBox boxes[3][kBinCapacity];
    alignas(16) std::int32_t counts[kBinCapacity][4];
    int count;

    explicit BinGrid(int bin_count) : count(bin_count) {
        for (int b = 0; b < count; ++b) {
            for (auto& axis : boxes) axis[b].clear();
            Int4(0).store_aligned(counts[b]);
        }
    }
    void merge(const BinGrid& other) {
        for (int b = 0; b < count; ++b) {
            for (int axis = 0; axis < 3; ++axis) boxes[axis][b].add(other.boxes[axis][b]);
            (Int4::load_aligned(counts[b]) + Int4::load_aligned(other.counts[b])).store_aligned(counts[b]);
        }
    }
};

/// Nodes at least this large alternate between two bin grids: a run of references that fall in
/// the same bin would otherwise make each update wait for the previous one's store.
constexpr std::uint32_t kTwoGridMin = 256;

/// Drops refs [begin, end) into the bins of every axis (AllAxes) or of `single_axis` only. The
/// bin index is computed exactly as BinMapping::bin computes it, so partition() agrees.
template <bool AllAxes>
void fill_bins(std::span<const PrimitiveRef> refs, std::uint32_t begin, std::uint32_t end, const BinMapping& mapping,
               int single_axis, BinGrid& grid) {
    const Float4 origin{mapping.origin[0], mapping.origin[1], mapping.origin[2], 0.0f};
    const Float4 scale{mapping.scale[0], mapping.scale[1], mapping.scale[2], 0.0f};
    const Int4 last_bin(mapping.count - 1);
    auto add = [&](const PrimitiveRef& ref, BinGrid& to) {
        const Float4 centroid = (load_lo(ref) + load_hi(ref)) * Float4(0.5f);
        alignas(16) std::int32_t bin[4];
        xsimd::min(xsimd::batch_cast<std::int32_t>((centroid - origin) * scale), last_bin).store_aligned(bin);
        const Float8 box = load_lo_negated_hi(ref);
        for (int axis = 0; axis < 3; ++axis) {
            if (!AllAxes && axis != single_axis) continue;
            to.boxes[axis][bin[axis]].add(box);
            ++to.counts[bin[axis]][axis];
        }
    };
    const PrimitiveRef* ref = refs.data();
    if (end - begin < kTwoGridMin) {
        for (std::uint32_t i = begin; i != end; ++i) add(ref[i], grid);
        return;
    }
    BinGrid odd(mapping.count);
    std::uint32_t i = begin;
    for (; i + 1 < end; i += 2) {
        add(ref[i], grid);
        add(ref[i + 1], odd);
    }
    if (i != end) add(ref[i], grid);
    grid.merge(odd);
}

void fill_bins(std::span<const PrimitiveRef> refs, const BuildRange& range, const BinMapping& mapping, int single_axis,
               BinGrid& grid) {
    auto fill = [&](std::uint32_t begin, std::uint32_t end, BinGrid& out) {
        if (single_axis < 0)
            fill_bins<true>(refs, begin, end, mapping, single_axis, out);
        else
            fill_bins<false>(refs, begin, end, mapping, single_axis, out);
    };
    if (range.count() < kParallelBinningMin) {
        fill(range.begin, range.end, grid);
        return;
    }
    // One grid per thread rather than a reduction of grid values, which would copy a grid (up
    // to 28 KiB) for every chunk; the merge is exact, so its order does not matter.
    tbb::combinable<BinGrid> per_thread([&] { return BinGrid(mapping.count); });
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(range.begin, range.end, kBinningGrain),
                      [&](const tbb::blocked_range<std::uint32_t>& r) { fill(r.begin(), r.end(), per_thread.local()); });
    per_thread.combine_each([&](const BinGrid& partial) { grid.merge(partial); });
}

/// The unions of the centroids that go left and of those that go right, each centroid computed as
/// PrimitiveRef::centroid computes it. Both are updated for every reference, through a select, so
/// the side taken is never a branch or a store the next update waits for.
struct SideCentroidBounds {
    Float4 lo[2] = {Float4(kInfinity), Float4(kInfinity)};
    Float4 hi[2] = {Float4(-kInfinity), Float4(-kInfinity)};

    void add(const PrimitiveRef& ref, bool goes_left) {
        const Float4 centroid = (load_lo(ref) + load_hi(ref)) * Float4(0.5f);
        const auto left = Float4::batch_bool_type(goes_left);
        lo[0] = xsimd::min(lo[0], xsimd::select(left, centroid, Float4(kInfinity)));
        hi[0] = xsimd::max(hi[0], xsimd::select(left, centroid, Float4(-kInfinity)));
        lo[1] = xsimd::min(lo[1], xsimd::select(left, Float4(kInfinity), centroid));
        hi[1] = xsimd::max(hi[1], xsimd::select(left, Float4(-kInfinity), centroid));
    }
    Aabb bounds(int side) const {
        alignas(16) float l[4], h[4];
        lo[side].store_aligned(l);
        hi[side].store_aligned(h);
        return {{l[0], l[1], l[2]}, {h[0], h[1], h[2]}};
    }
};

/// Where a reference's centroid falls along Axis, in bins of a BinMapping (origin, scale): exactly
/// as fill_bins computes it (centroid, minus origin, times scale), so every pass puts a reference
/// in the same bin.
template <int Axis>
float bin_position(const PrimitiveRef& ref, float origin, float scale) {
    return ((ref.lo[Axis] + ref.hi[Axis]) * 0.5f - origin) * scale;
}

/// Returns f.template operator()<Axis>() for Axis = axis (0, 1 or 2): the per-axis loops take the
/// axis as a template parameter so that coordinates load from fixed offsets.
template <class F>
decltype(auto) on_axis(int axis, F&& f) {
    switch (axis) {
        case 0:
            return f.template operator()<0>();
        case 1:
            return f.template operator()<1>();
        default:
            return f.template operator()<2>();
    }
}

/// Partitions refs [begin, end) in place: those whose bin position on Axis goes_left(position)
/// accepts to the front. Returns the end of the left ones. Without branches (a data-dependent
/// branch would mispredict half the time): each reference is swapped with the first right one
/// and the left end advances when it went left (Lomuto's scheme), so refs [begin, left_end) go
/// left and [left_end, i) go right after step i. Axis is a template parameter so the coordinates
/// load from fixed offsets.
template <int Axis, class GoesLeft>
std::uint32_t partition_by_position(PrimitiveRef* refs, std::uint32_t begin, std::uint32_t end, float origin,
                                    float scale, GoesLeft goes_left, SideCentroidBounds& centroids) {
    std::uint32_t left_end = begin;
    for (std::uint32_t i = begin; i != end; ++i) {
        const bool left = goes_left(bin_position<Axis>(refs[i], origin, scale));
        centroids.add(refs[i], left);
        const Float8 ref = load_whole(refs[i]);
        load_whole(refs[left_end]).store_aligned(reinterpret_cast<float*>(refs + i));
        ref.store_aligned(reinterpret_cast<float*>(refs + left_end));
        left_end += left;
    }
    return left_end;
}

Aabb union_of_bins(const BinBox* boxes, int first, int last) {
    BinBox all;
    all.clear();
    for (int b = first; b <= last; ++b) all.add(boxes[b]);
    return all.bounds();
}

/// Growing boxes of the three axes, each as x, y, z lanes of lo and -hi.
struct AxisBoxes {
    Float4 lo[3] = {Float4(kInfinity), Float4(kInfinity), Float4(kInfinity)};
    Float4 negated_hi[3] = {Float4(kInfinity), Float4(kInfinity), Float4(kInfinity)};

    void add(const BinGrid& grid, int bin) {
        for (int axis = 0; axis < 3; ++axis) {
            lo[axis] = xsimd::min(lo[axis], grid.boxes[axis][bin].lo());
            negated_hi[axis] = xsimd::min(negated_hi[axis], grid.boxes[axis][bin].negated_hi());
        }
    }
    /// The three surface areas, one lane per axis, by the formula of Aabb::surface_area (a box
    /// still empty gives +inf, never NaN).
    Float4 surface_areas() const {
        using Double2 = xsimd::batch<double, Float4::arch_type>;
        // -(-hi) is hi exactly, so the extents are those of Aabb::extent bit for bit.
        const Float4 e0 = -negated_hi[0] - lo[0], e1 = -negated_hi[1] - lo[1], e2 = -negated_hi[2] - lo[2];
        const Float4 zero(0.0f);
        // Transpose the extents so that ex holds the x extents of the three boxes, and so on.
        const Double2 xy01 = xsimd::bitwise_cast<Double2>(xsimd::zip_lo(e0, e1));   // x0 x1 y0 y1
        const Double2 zw01 = xsimd::bitwise_cast<Double2>(xsimd::zip_hi(e0, e1));   // z0 z1 . .
        const Double2 xy2 = xsimd::bitwise_cast<Double2>(xsimd::zip_lo(e2, zero));  // x2 0 y2 0
        const Double2 zw2 = xsimd::bitwise_cast<Double2>(xsimd::zip_hi(e2, zero));  // z2 0 . .
        const Float4 ex = xsimd::bitwise_cast<Float4>(xsimd::zip_lo(xy01, xy2));
        const Float4 ey = xsimd::bitwise_cast<Float4>(xsimd::zip_hi(xy01, xy2));
        const Float4 ez = xsimd::bitwise_cast<Float4>(xsimd::zip_lo(zw01, zw2));
        return Float4(2.0f) * (ex * ey + ey * ez + ez * ex);
    }
};

/// The cheapest boundary between bins, evaluated for the three axes at once (one lane each, as
/// Embree's binner does). Axes that were not binned or cannot be split have all their
/// references in one bin and so offer no boundary with references on both sides.
BinnedSahSplitter::Split cheapest_boundary(const BinGrid& grid, const BvhOptions& options, float node_area) {
    const int n = grid.count;
    alignas(16) float right_area[kBinCapacity][4];
    alignas(16) std::int32_t right_count[kBinCapacity][4];
    AxisBoxes boxes;
    Int4 count(0);
    for (int b = n - 1; b > 0; --b) {
        boxes.add(grid, b);
        count += Int4::load_aligned(grid.counts[b]);
        boxes.surface_areas().store_aligned(right_area[b]);
        count.store_aligned(right_count[b]);
    }
    const Float4 traversal(options.traversal_cost * node_area), intersection(options.intersection_cost);
    const Float4 zero(0.0f);
    Float4 best_cost(kInfinity), best_bin(0.0f);  // bin numbers are small, exact as floats
    boxes = AxisBoxes{};
    count = Int4(0);
    for (int b = 0; b < n - 1; ++b) {
        boxes.add(grid, b);
        count += Int4::load_aligned(grid.counts[b]);
        const Float4 left_count = xsimd::batch_cast<float>(count);
        const Float4 right_count_b = xsimd::batch_cast<float>(Int4::load_aligned(right_count[b + 1]));
        const Float4 cost = traversal + intersection * (boxes.surface_areas() * left_count +
                                                        Float4::load_aligned(right_area[b + 1]) * right_count_b);
        const auto better = (left_count > zero) & (right_count_b > zero) & (cost < best_cost);
        best_cost = xsimd::select(better, cost, best_cost);
        best_bin = xsimd::select(better, Float4(float(b)), best_bin);
    }
    alignas(16) float costs[4], bins[4];
    best_cost.store_aligned(costs);
    best_bin.store_aligned(bins);
    BinnedSahSplitter::Split best;
    for (int axis = 0; axis < 3; ++axis)
        if (costs[axis] < best.cost) {  // ties keep the lower axis
            best.axis = axis;
            best.last_left_bin = int(bins[axis]);
            best.cost = costs[axis];
        }
    for (int b = 0; best.axis >= 0 && b <= best.last_left_bin; ++b)
        best.left_count += std::uint32_t(grid.counts[b][best.axis]);
    return best;
}

/// The fine bins of a refined split: the two bins either side of the best boundary, each cut
/// into kFineBinsPerBin, along the split's axis.
struct FineBins {
    static constexpr int kCount = 2 * BinnedSahSplitter::kFineBinsPerBin;
    BinBox boxes[kCount];
    std::uint32_t counts[kCount] = {};

    FineBins() {
        for (BinBox& box : boxes) box.clear();
    }
};

/// Drops the references of bins first_bin and first_bin + 1 into the fine bins. A reference's bin
/// is int(position) clamped to last_bin, so it is one of the two exactly when first_bin <=
/// position < first_bin + 2, or position >= first_bin when first_bin + 1 is the last bin (which
/// also holds the positions at its end): compared as floats, without converting every position.
///
/// Which references lie in the two bins is found 64 at a time into a bit mask, and only its set
/// bits are visited. The two comparisons are combined with &: with &&, the compiler branched on
/// the first, whose outcome follows no pattern along a node's references, and the pass cost more
/// than binning the node (15 against 12 cycles a reference on Buddha).
template <int Axis>
void fill_fine_bins(const PrimitiveRef* refs, std::uint32_t begin, std::uint32_t end, float origin, float scale,
                    int first_bin, int last_bin, FineBins& fine) {
    const float first = float(first_bin), fine_scale = float(BinnedSahSplitter::kFineBinsPerBin);
    const float past = first_bin + 1 == last_bin ? kInfinity : float(first_bin + 2);
    for (std::uint32_t block = begin; block < end; block += 64) {
        const std::uint32_t block_end = std::min(end, block + 64);
        std::uint64_t inside = 0;
        for (std::uint32_t i = block; i != block_end; ++i) {
            const float position = bin_position<Axis>(refs[i], origin, scale);
            inside |= std::uint64_t((position >= first) & (position < past)) << (i - block);
        }
        for (; inside != 0; inside &= inside - 1) {
            const std::uint32_t i = block + std::uint32_t(std::countr_zero(inside));
            const float position = bin_position<Axis>(refs[i], origin, scale);
            const int f = std::min(int((position - first) * fine_scale), FineBins::kCount - 1);
            fine.boxes[f].add(load_lo_negated_hi(refs[i]));
            ++fine.counts[f];
        }
    }
}

void refine_split(std::span<const PrimitiveRef> refs, const BuildRange& range, const BinMapping& mapping,
                  const BinGrid& grid, const BvhOptions& options, BinnedSahSplitter::Split& best) {
    const int axis = best.axis, first_bin = best.last_left_bin;
    if (first_bin + 1 >= grid.count) return;
    FineBins fine;
    on_axis(axis, [&]<int Axis>() {
        fill_fine_bins<Axis>(refs.data(), range.begin, range.end, mapping.origin[Axis], mapping.scale[Axis], first_bin,
                             grid.count - 1, fine);
    });

    // What lies outside the two bins stays on its side whatever the fine boundary.
    BinBox below, above;
    below.clear();
    above.clear();
    std::uint32_t below_count = 0, above_count = 0;
    for (int b = 0; b < first_bin; ++b) {
        below.add(grid.boxes[axis][b]);
        below_count += std::uint32_t(grid.counts[b][axis]);
    }
    for (int b = first_bin + 2; b < grid.count; ++b) {
        above.add(grid.boxes[axis][b]);
        above_count += std::uint32_t(grid.counts[b][axis]);
    }
    float right_area[FineBins::kCount];
    std::uint32_t right_count[FineBins::kCount];
    BinBox right = above;
    std::uint32_t count = above_count;
    for (int f = FineBins::kCount - 1; f > 0; --f) {
        right.add(fine.boxes[f]);
        count += fine.counts[f];
        right_area[f] = right.bounds().surface_area();
        right_count[f] = count;
    }
    const float traversal = options.traversal_cost * range.bounds.surface_area();
    BinBox left = below;
    count = below_count;
    for (int f = 0; f + 1 < FineBins::kCount; ++f) {
        left.add(fine.boxes[f]);
        count += fine.counts[f];
        if (count == 0 || right_count[f + 1] == 0) continue;
        const float cost = traversal + options.intersection_cost * (left.bounds().surface_area() * float(count) +
                                                                    right_area[f + 1] * float(right_count[f + 1]));
        if (cost < best.cost) {  // ties keep the bin boundary (the middle fine boundary is the same split)
            best.cost = cost;
            best.left_count = count;
            best.refined = true;
            best.fine_last_left = f;
        }
    }
    if (!best.refined) return;
    BinBox left_box = below, right_box = above;
    for (int f = 0; f < FineBins::kCount; ++f) (f <= best.fine_last_left ? left_box : right_box).add(fine.boxes[f]);
    best.left_bounds = left_box.bounds();
    best.right_bounds = right_box.bounds();
}

}  // namespace

BinMapping::BinMapping(const Aabb& centroid_bounds, int bin_count) : count(bin_count) {
    for (int axis = 0; axis < 3; ++axis) {
        const float extent = centroid_bounds.hi[axis] - centroid_bounds.lo[axis];
        const float s = extent > 0.0f ? float(bin_count) / extent : 0.0f;
        origin[axis] = centroid_bounds.lo[axis];
        scale[axis] = std::isfinite(s) ? s : 0.0f;  // an extent too small to divide by cannot be binned
    }
}

BinnedSahSplitter::BinnedSahSplitter(std::span<PrimitiveRef> refs, const BvhOptions& options)
    : refs_(refs), options_(options) {}

int BinnedSahSplitter::bins_for_count(std::uint32_t count) const {
    if (count >= BvhOptions::kLargeNodeMin) return options_.large_node_bin_count;
    return int(std::min<std::uint32_t>(std::uint32_t(options_.bin_count), 4u + count / 4u));
}

BinnedSahSplitter::Split BinnedSahSplitter::find_sah_split(const BuildRange& range) const {
    if (range.count() == 2) return split_pair(range);
    Split best;
    const BinMapping mapping(range.centroid_bounds, bins_for_count(range.count()));
    const int single_axis = options_.all_axes ? -1 : range.centroid_bounds.largest_axis();
    if (single_axis >= 0 ? !mapping.can_split(single_axis)
                         : !(mapping.can_split(0) || mapping.can_split(1) || mapping.can_split(2)))
        return best;
    BinGrid grid(mapping.count);
    fill_bins(refs_, range, mapping, single_axis, grid);
    best = cheapest_boundary(grid, options_, range.bounds.surface_area());
    if (best.axis >= 0) {
        best.left_bounds = union_of_bins(grid.boxes[best.axis], 0, best.last_left_bin);
        best.right_bounds = union_of_bins(grid.boxes[best.axis], best.last_left_bin + 1, grid.count - 1);
        if (range.count() >= kRefineMin && range.count() < kRefineEnd)
            refine_split(refs_, range, mapping, grid, options_, best);
    }
    return best;
}

BinnedSahSplitter::Split BinnedSahSplitter::split_pair(const BuildRange& range) const {
    Split split;
    const int axis = range.centroid_bounds.largest_axis();
    if (!(range.centroid_bounds.hi[axis] > range.centroid_bounds.lo[axis])) return split;  // coinciding centroids
    const PrimitiveRef& a = refs_[range.begin];
    const PrimitiveRef& b = refs_[range.begin + 1];
    const bool a_first = a.centroid(axis) < b.centroid(axis);
    split.axis = axis;
    split.left_count = 1;
    split.left_bounds = (a_first ? a : b).bounds();
    split.right_bounds = (a_first ? b : a).bounds();
    split.cost = options_.traversal_cost * range.bounds.surface_area() +
                 options_.intersection_cost * (split.left_bounds.surface_area() + split.right_bounds.surface_area());
    return split;
}

ChildRanges BinnedSahSplitter::partition(const BuildRange& range, const Split& split) {
    if (range.count() == 2) {
        PrimitiveRef* pair = refs_.data() + range.begin;
        if (!(pair[0].centroid(split.axis) < pair[1].centroid(split.axis))) std::swap(pair[0], pair[1]);
        return {{range.begin, range.begin + 1, split.left_bounds, {pair[0].centroid(), pair[0].centroid()}},
                {range.begin + 1, range.end, split.right_bounds, {pair[1].centroid(), pair[1].centroid()}},
                split.axis};
    }
    const BinMapping mapping(range.centroid_bounds, bins_for_count(range.count()));
    const int axis = split.axis;
    // A reference goes left when its bin, int(position), is at most last_left_bin: for the
    // position >= 0 that centroids at or beyond the origin have, that is position < bin + 1.
    // A refined split also takes the fine bins up to fine_last_left of the two bins from
    // last_left_bin on: a fine bin is int((position - last_left_bin) * kFineBinsPerBin), as
    // fill_fine_bins computes it, so the test is (position - last_left_bin) * kFineBinsPerBin <
    // fine_last_left + 1. It also sends left every position below last_left_bin (a negative
    // difference) and right every one past the two bins (fine_last_left + 1 < 2 * kFineBinsPerBin).
    const float left_limit = float(split.last_left_bin + 1), first_fine = float(split.last_left_bin);
    const float fine_limit = float(split.fine_last_left + 1), fine_scale = float(kFineBinsPerBin);
    SideCentroidBounds centroids;
    const std::uint32_t left_end = on_axis(axis, [&]<int Axis>() {
        if (split.refined)
            return partition_by_position<Axis>(
                refs_.data(), range.begin, range.end, mapping.origin[Axis], mapping.scale[Axis],
                [&](float position) { return (position - first_fine) * fine_scale < fine_limit; }, centroids);
        return partition_by_position<Axis>(
            refs_.data(), range.begin, range.end, mapping.origin[Axis], mapping.scale[Axis],
            [&](float position) { return position < left_limit; }, centroids);
    });
    assert(left_end - range.begin == split.left_count);
    return {{range.begin, left_end, split.left_bounds, centroids.bounds(0)},
            {left_end, range.end, split.right_bounds, centroids.bounds(1)},
            axis};
}

ChildRanges BinnedSahSplitter::partition_median(const BuildRange& range) {
    const int axis = range.centroid_bounds.largest_axis();
    const std::uint32_t mid = range.begin + range.count() / 2;
    std::nth_element(
        refs_.begin() + range.begin, refs_.begin() + mid, refs_.begin() + range.end,
        [axis](const PrimitiveRef& a, const PrimitiveRef& b) { return a.centroid(axis) < b.centroid(axis); });
    ChildRanges out{{range.begin, mid, {}, {}}, {mid, range.end, {}, {}}, axis};
    for (BuildRange* side : {&out.left, &out.right})
        for (std::uint32_t i = side->begin; i != side->end; ++i) {
            side->bounds.extend(refs_[i].bounds());
            side->centroid_bounds.extend(refs_[i].centroid());
        }
    return out;
}

}  // namespace trident::bvh
