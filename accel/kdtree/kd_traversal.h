#pragma once
// Scalar kd-tree traversal, front to back with a fixed stack of (node, t_min, t_max): the
// recursive ray traversal of Havran's thesis (TA_rec_B) in pbrt's iterative form.
//
// The ray is first clipped to the scene box (core/slab_test.h). At an interior node the plane
// distance t_split = (split - origin) * inv_dir decides: the near child alone (the ray leaves the
// current interval before the plane), the far child alone (it crossed the plane before the
// interval), or both, near first with [t_min, t_split] and far pushed with [t_split, t_max]. The
// near child is the one below the plane when the direction is >= +0 (by its sign bit), so zero
// components need no branch: 1/+-0 = +-inf sends t_split to +-inf on the correct side.
//
// A ray lying in a split plane (direction component +-0 and origin exactly on the plane) gives
// 0 * inf = NaN. Both children are then visited over the whole interval: triangles lying in the
// plane sit on whichever side the builder's SAH chose, and triangles touching the plane from
// either side can be hit edge-on.
//
// Hits and termination: a hit found in a leaf is a true hit of the ray wherever it lies, so it is
// kept even when it lies beyond the leaf's cell (a triangle straddling cells), and it bounds all
// later tests. A pending cell is skipped when its entry distance lies beyond the best hit: no
// hit in it can be closer. This is pbrt's rule, and it is correct for straddling triangles without
// mailboxing and without discarding out-of-cell hits. Pending cells are skipped rather than the
// traversal stopped, because the in-plane case pushes a cell whose entry is not the largest.
//
// Widening: t_split and the interval ends each carry up to three roundings (gamma(3) relative,
// Ize 2013). Comparisons that decide whether to leave out a cell, and the skip test against the
// best hit, therefore allow 2 gamma(3) of slack: a cell the ray meets only within rounding of its
// boundary is visited rather than dropped, so a triangle touching that boundary from inside is
// still found. The cost is a rare extra cell. SlabTest::fast leaves the slack (and the scene-box
// safeguards of core/slab_test.h) out, to measure what they cost.
//
// Empty leaves: an interior node marks its children that are empty leaves (kd_node.h), and the
// walk neither fetches nor pushes them. Nothing else changes: the cells it then goes to, and the
// tests on leaving a pending cell out, are those the visit of the empty leaf would have led to.
//
// Any-hit queries return at the first triangle hit in [ray.tmin, ray.tmax).
#include <cmath>
#include <cstdint>
#include <span>

#include "accel/kdtree/kd_node.h"
#include "core/aabb.h"
#include "core/flatten.h"
#include "core/intersect_triangle.h"
#include "core/lanes.h"
#include "core/mesh.h"
#include "core/ray.h"
#include "core/slab_test.h"

namespace trident {

enum class KdQuery { closest_hit, any_hit };

/// The flattened tree as the traversals read it.
struct KdTreeView {
    std::span<const KdNode> nodes;               // nodes[0] is the root; empty for an empty tree
    std::span<const TriangleId> leaf_triangles;  // leaves' runs of indices into `triangles`
    std::span<const Triangle> triangles;         // corners, in the builder's order
    std::span<const TriangleId> triangle_ids;    // the file index of each of `triangles`: what hits report
    Aabb bounds;                                 // the root's cell
};

namespace detail {

inline constexpr float kKdSlack = 2.0f * rounding_gamma(3);
// Written over float or a batch (Lanes<T>), so a packet lane widens exactly as the single ray.
// SlabTest::fast compares the rounded distances as they are (no slack).
template <SlabTest Slabs, class T>
T widened_up(T t) {
    if constexpr (Slabs == SlabTest::fast)
        return t;
    else
        return t + Lanes<T>::abs(t) * T(kKdSlack);
}
template <SlabTest Slabs, class T>
T widened_down(T t) {
    if constexpr (Slabs == SlabTest::fast)
        return t;
    else
        return t - Lanes<T>::abs(t) * T(kKdSlack);
}

}  // namespace detail

/// The walk below `start` for the ray's interval [t_min, t_max] in that cell, with `best` holding
/// the closest hit so far (best.t is the limit: ray.tmax or a closer hit). Returns true when a
/// hit was recorded in `best` (any-hit queries: at the first one). The whole traversal starts it
/// at the root; packet traversals hand it the subtrees that only a few lanes still need, and a
/// lane walked so from a cell visits what the whole traversal visits from there.
///
/// Flattened (every call in it inlined): since it learned to skip empty leaves, gcc otherwise
/// leaves the triangle test out of line here, a call per triangle that cost up to 20%
/// (bench/experiments/packets.md).
template <KdQuery Query, TriangleTest Test, SlabTest Slabs, class Counters>
TRIDENT_FLATTEN bool walk_kdtree(const KdTreeView& tree, const Ray& ray, const SlabRay& slab,
                                 const TriangleIntersector<Test>& intersector, std::uint32_t start, float t_min,
                                 float t_max, Hit& best, Counters& counters) {
    using detail::widened_down;
    using detail::widened_up;
    struct Pending {
        std::uint32_t node;
        float t_min, t_max;
    };
    Pending stack[kKdMaxDepth];
    int pending = 0;
    bool found = false;
    std::uint32_t index = start;
    for (;;) {
        counters.visit_node();
        const KdNode node = tree.nodes[index];
        if (!node.is_leaf()) {
            const int axis = node.axis();
            const float t_split = (node.split() - ray.origin[axis]) * slab.inv_dir[axis];
            const bool below_first = !std::signbit(ray.dir[axis]);
            const std::uint32_t near = below_first ? node.below_child() : node.above_child();
            const std::uint32_t far = below_first ? node.above_child() : node.below_child();
            // An empty leaf is neither visited nor pushed: what follows it is what its visit
            // would have led to.
            const bool near_empty = below_first ? node.below_empty() : node.above_empty();
            const bool far_empty = below_first ? node.above_empty() : node.below_empty();
            if (std::isnan(t_split)) {  // the ray lies in the plane
                if (!far_empty) stack[pending++] = {far, t_min, t_max};
                if (!near_empty) {
                    index = near;
                    continue;
                }
            } else if (t_split > widened_up<Slabs>(t_max)) {
                if (!near_empty) {
                    index = near;
                    continue;
                }
            } else if (t_split < widened_down<Slabs>(t_min)) {
                if (!far_empty) {
                    index = far;
                    continue;
                }
            } else {
                if (!far_empty) stack[pending++] = {far, t_split, t_max};
                if (!near_empty) {
                    index = near;
                    t_max = t_split;
                    continue;
                }
            }
        } else {
            const TriangleId* ids = tree.leaf_triangles.data() + node.triangle_offset();
            for (std::uint32_t i = 0; i < node.triangle_count(); ++i) {
                counters.test_triangle();
                TriangleHit h;
                if (intersector.intersect(tree.triangles[ids[i]], best.t, h)) {
                    best = {tree.triangle_ids[ids[i]], h.t, h.u, h.v};
                    found = true;
                    if constexpr (Query == KdQuery::any_hit) return true;
                }
            }
        }
        // The next pending cell that may hold a closer hit.
        do {
            if (pending == 0) return found;
            --pending;
        } while (stack[pending].t_min > widened_up<Slabs>(best.t));
        index = stack[pending].node;
        t_min = stack[pending].t_min;
        t_max = stack[pending].t_max;
    }
}

template <KdQuery Query, TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Counters>
Hit traverse_kdtree(const KdTreeView& tree, const Ray& ray, Counters& counters) {
    Hit best;
    const SlabRay slab(ray.origin, ray.dir);
    float t_min, t_max;
    if (tree.nodes.empty() ||
        !clip_to_box<Slabs>(slab, tree.bounds.lo, tree.bounds.hi, ray.tmin, ray.tmax, t_min, t_max))
        return best;
    best.t = ray.tmax;
    const TriangleIntersector<Test> intersector(ray);
    if (!walk_kdtree<Query, Test, Slabs>(tree, ray, slab, intersector, 0, t_min, t_max, best, counters))
        best.t = kInfinity;
    return best;
}

}  // namespace trident
