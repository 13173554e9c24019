// Choosing a node's plane from its event lists: the exact SAH sweep of each axis (sah_sweep.h),
// after Wald and Havran, "On building fast kd-trees for ray tracing, and on doing that in
// O(N log N)" (RT 2006), section 4.2.
#include <array>

#include "accel/kdtree/kd_builder.h"
#include "simd/width.h"

namespace trident::kd {

bool avx512_file_searches_runnable() {
    return TRIDENT_PORTABLE_BUILD && !TRIDENT_KD_AVX512 && is_runnable(SimdWidth::w16);
}

Split SahBuilder::find_split(const NodeWork& node) const {
    std::array<Split, 3> best;
    for_each_axis(parallel_axes(node.size()), [&](int axis) { best[axis] = sweep(node, axis); });
    Split out;
    for (const Split& s : best)
        if (s.cost < out.cost) out = s;  // ties to the lower axis
    return out;
}

Split SahBuilder::sweep(const NodeWork& node, int axis) const {
    const AxisSetup setup = axis_setup(node.cell, axis, node.size());
    if (!(setup.half_area > 0.0)) return {};
    const SweepBest best = sweep_events(node.events[axis], setup.sweep, avx512_file_searches_);
    if (!best.found()) return {};
    return {axis, node.events[axis][best.tag >> 1].position, (best.tag & 1u) != 0,
            split_cost(best.weighted(), setup.half_area)};
}

}  // namespace trident::kd
