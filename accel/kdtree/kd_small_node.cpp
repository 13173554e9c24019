// The small-node search (kd_builder.h, SmallNode): a node of a few triangles and its whole subtree
// built from its triangles' boxes in fixed arrays, planes found by counting (count_planes in
// sah_sweep.h) and triangles split by comparing box ends with the plane.
#include <algorithm>
#include <array>

#include "accel/kdtree/clip_triangle.h"
#include "accel/kdtree/kd_builder.h"

namespace trident::kd {

SmallNode SahBuilder::small_node_of(const NodeWork& node) {
    SmallNode small;
    small.cell = node.cell;
    small.count = node.size();
    std::copy(node.prims.begin(), node.prims.end(), small.prims.begin());
    small.pad();
    for (int axis = 0; axis < 3; ++axis) {
        BoxEnds<kSmallNode>& ends = small.axes[axis];
        for (const Event& e : node.events[axis]) {
            if (e.type() != EventType::end) ends.lo[e.prim()] = e.position;
            if (e.type() != EventType::start) ends.hi[e.prim()] = e.position;
        }
    }
    return small;
}

void SahBuilder::build_small(const SmallNode& node, Subtree& out, std::size_t slot, int depth, int bad_refines) const {
    Split split;
    if (node.count > options_.leaf_triangles && depth < max_depth_)
        split = judged(find_small_split(node), node.count, bad_refines);
    if (!split.found()) {
        make_leaf(node.triangles(), out, slot);
        return;
    }
    SmallNode below, above;
    split_small(node, split, below, above);
    const std::size_t first_child = out.nodes.size();
    out.nodes[slot] = KdNode::interior(split.axis, split.position, first_child);
    out.nodes.push_back(kPlaceholder);
    out.nodes.push_back(kPlaceholder);
    build_small(below, out, first_child, depth + 1, bad_refines);
    build_small(above, out, first_child + 1, depth + 1, bad_refines);
}

Split SahBuilder::find_small_split(const SmallNode& node) const {
    Split out;
    for (int axis = 0; axis < 3; ++axis) {
        const AxisSetup setup = axis_setup(node.cell, axis, node.count);
        if (!(setup.half_area > 0.0)) continue;
        const CountedPlane plane = count_planes(node.axes[axis], node.count, setup.sweep, avx512_file_searches_);
        if (!plane.found()) continue;
        const double cost = split_cost(plane.weighted(), setup.half_area);
        if (cost < out.cost) out = {axis, plane.position, plane.planars_below, cost};  // ties to the lower axis
    }
    return out;
}

void SahBuilder::split_small(const SmallNode& node, const Split& split, SmallNode& below, SmallNode& above) const {
    const int k = split.axis;
    const float p = split.position;
    below.cell = above.cell = node.cell;
    below.cell.hi[k] = p;
    above.cell.lo[k] = p;
    std::array<std::uint32_t, kSmallNode> straddlers;
    std::size_t straddler_count = 0;
    auto ends_of = [&](std::size_t i, float(&lo)[3], float(&hi)[3]) {
        for (int axis = 0; axis < 3; ++axis) {
            lo[axis] = node.axes[axis].lo[i];
            hi[axis] = node.axes[axis].hi[i];
        }
    };
    for (std::size_t i = 0; i < node.count; ++i) {
        const float lo_k = node.axes[k].lo[i], hi_k = node.axes[k].hi[i];
        const bool flat = lo_k == hi_k;
        const bool goes_below = flat ? lo_k < p || (lo_k == p && split.planars_below) : hi_k <= p;
        const bool goes_above = flat ? lo_k > p || (lo_k == p && !split.planars_below) : lo_k >= p;
        if (!goes_below && !goes_above) {
            straddlers[straddler_count++] = std::uint32_t(i);
            continue;
        }
        float lo[3], hi[3];
        ends_of(i, lo, hi);
        (goes_below ? below : above).add(node.prims[i], lo, hi);
    }
    for (std::size_t j = 0; j < straddler_count; ++j) {
        const std::uint32_t i = straddlers[j];
        if (!options_.perfect_splits) {
            float lo[3], hi[3];
            ends_of(i, lo, hi);
            const float hi_k = hi[k];
            hi[k] = p;
            below.add(node.prims[i], lo, hi);
            hi[k] = hi_k;
            lo[k] = p;
            above.add(node.prims[i], lo, hi);
            continue;
        }
        // As split_node clips them: both empty only through rounding, for a triangle touching
        // the plane, and then the clamped boxes go to both sides.
        const std::uint32_t id = node.prims[i];
        std::array<Aabb, 2> boxes{intersection(bounds_[id], below.cell), intersection(bounds_[id], above.cell)};
        const auto clipped_below = clipped_triangle_bounds(triangles_[id], below.cell);
        const auto clipped_above = clipped_triangle_bounds(triangles_[id], above.cell);
        const bool both = !clipped_below && !clipped_above;
        if (clipped_below) boxes[0] = *clipped_below;
        if (clipped_above) boxes[1] = *clipped_above;
        for (int c = 0; c < 2; ++c) {
            if (!both && !(c == 0 ? clipped_below : clipped_above)) continue;
            const float lo[3] = {boxes[c].lo.x, boxes[c].lo.y, boxes[c].lo.z};
            const float hi[3] = {boxes[c].hi.x, boxes[c].hi.y, boxes[c].hi.z};
            (c == 0 ? below : above).add(id, lo, hi);
        }
    }
    below.pad();
    above.pad();
}

}  // namespace trident::kd
