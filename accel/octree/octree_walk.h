#pragma once
// The parametric octree walk of Revelles, Ureña and Lastra ("An Efficient Parametric Algorithm
// for Octree Traversal", WSCG 2000). A node is described by the ray parameters where the ray
// crosses its six slab planes (t0 entering, t1 leaving, per axis); the children's parameters are
// halves of those, split at the midpoints tm, so no cell bounds are needed below the root.
//
// The ray is mirrored so every direction component is positive: a negative axis swaps its two
// planes, and the child indices of the mirrored walk are XOR'ed with the mirror mask (the paper's
// `a`) to get the real ones. Our child numbering (bit 0 = x, 1 = y, 2 = z, see octree_node.h)
// gives the paper's first-node and next-node rules (its Tables 1 and 2, whose published bit
// order has an erratum) in closed form:
//   first child: bit i set iff tm_i < the entry parameter max(t0) (the ray enters past the plane);
//   next child:  leave through the axis with the smallest exit parameter; if the current child is
//                already in the upper half of that axis the ray leaves the parent (8 = done).
//
// Rays parallel to an axis (a zero direction component, or one so small that its slab parameters
// overflow) never cross that axis' planes: their parameters are -inf/+inf and the midpoint is
// +inf or -inf depending on the side of the centre plane the origin lies on, instead of the
// paper's tiny-epsilon direction (which would change results) and instead of the NaN that
// 0.5 * (-inf + inf) would give.
#include <cmath>

#include "accel/octree/octree_node.h"
#include "core/lanes.h"
#include "core/ray.h"
#include "core/slab_test.h"

namespace trident {

/// What the walk needs to know about a ray beyond its node parameters.
struct OctreeWalkRay {
    Vec3f origin;
    unsigned mirror = 0;    // bit i: direction component i is negative (the paper's `a`)
    unsigned parallel = 0;  // bit i: the ray never crosses a plane of axis i
};

/// A node's slab parameters along the mirrored ray: t0[i] <= t1[i] for every axis. Over float for
/// one ray, over a batch for a packet (octree_packet_walk.h), with the same rounding lane by lane.
template <class T>
struct NodeSlabsT {
    Vec3T<T> t0, t1;

    T t_enter() const { return Lanes<T>::max(Lanes<T>::max(t0.x, t0.y), t0.z); }
    T t_exit() const { return Lanes<T>::min(Lanes<T>::min(t1.x, t1.y), t1.z); }
};
using NodeSlabs = NodeSlabsT<float>;

/// The slabs of the root cube along the whole line of the ray (not clipped to tmin/tmax).
/// Returns false when the line runs parallel to an axis outside the cube's slab on that axis, or
/// its direction is zero.
inline bool enter_root(const Ray& ray, const OctreeCube& cube, OctreeWalkRay& walk, NodeSlabs& slabs) {
    walk = {ray.origin, 0u, 0u};
    for (int axis = 0; axis < 3; ++axis) {
        const float lo = cube.lo[axis], hi = cube.lo[axis] + cube.size, o = ray.origin[axis];
        const float inv = 1.0f / ray.dir[axis];
        // Mirroring a negative axis is swapping its planes: (lo - o') / -d = (hi - o) / d.
        const bool negative = ray.dir[axis] < 0.0f;
        const float t_lo = ((negative ? hi : lo) - o) * inv, t_hi = ((negative ? lo : hi) - o) * inv;
        if (std::isfinite(t_lo) && std::isfinite(t_hi)) {
            slabs.t0[axis] = t_lo;
            slabs.t1[axis] = t_hi;
            if (negative) walk.mirror |= 1u << axis;
        } else {
            if (o < lo || o > hi) return false;
            slabs.t0[axis] = -kInfinity;
            slabs.t1[axis] = kInfinity;
            walk.parallel |= 1u << axis;
        }
    }
    return walk.parallel != 7u;
}

/// The parameters where the ray crosses the node's three centre planes. `cell` is the node's
/// real (unmirrored) cell, read only on parallel axes.
inline Vec3f slab_midpoints(const OctreeWalkRay& walk, const NodeSlabs& slabs, const OctreeCube& cell) {
    Vec3f tm;
    const Vec3f mid = cell.mid();
    for (int axis = 0; axis < 3; ++axis)
        tm[axis] = (walk.parallel >> axis) & 1u ? (walk.origin[axis] < mid[axis] ? kInfinity : -kInfinity)
                                                : 0.5f * (slabs.t0[axis] + slabs.t1[axis]);
    return tm;
}

/// The first child (mirrored numbering) the line enters.
inline unsigned first_child(const NodeSlabs& slabs, const Vec3f& tm) {
    const float t_enter = slabs.t_enter();
    return (tm.x < t_enter ? 1u : 0u) | (tm.y < t_enter ? 2u : 0u) | (tm.z < t_enter ? 4u : 0u);
}

/// Child `child`'s (mirrored numbering) slabs: the lower or upper half of each parent interval.
/// Built in one expression, not by assigning a default (zeroed) value axis by axis: over batches
/// the zeroing was a `rep stos` per child visited in the portable build (generic tuning).
template <class T>
NodeSlabsT<T> child_slabs(unsigned child, const NodeSlabsT<T>& parent, const Vec3T<T>& tm) {
    const auto enter = [&](int axis) { return (child >> axis) & 1u ? tm[axis] : parent.t0[axis]; };
    const auto leave = [&](int axis) { return (child >> axis) & 1u ? parent.t1[axis] : tm[axis]; };
    return {{enter(0), enter(1), enter(2)}, {leave(0), leave(1), leave(2)}};
}

/// The child entered after leaving `child` (mirrored numbering), or 8 when the ray leaves the
/// parent. Ties (the ray crossing an edge) go to the lower axis; the child passed through then has
/// an empty interval, which costs a visit but loses nothing.
inline unsigned next_child(unsigned child, const NodeSlabs& child_slabs_) {
    const Vec3f& t1 = child_slabs_.t1;
    const int axis = t1.x <= t1.y ? (t1.x <= t1.z ? 0 : 2) : (t1.y <= t1.z ? 1 : 2);
    const unsigned bit = 1u << axis;
    return (child & bit) ? 8u : (child | bit);
}

/// Whether the walk through a node (its slabs and midpoints) enters child `child` (mirrored
/// numbering). A child whose interval has a positive length always is (for t inside it, the walk
/// reaches the child holding the axes with tm < t, having added them in order of tm) and one with
/// an empty interval never is; this settles the children the line only touches at an edge or a
/// corner (a one-point interval), where the walk's tie rule decides.
inline bool walk_enters(unsigned child, const NodeSlabs& slabs, const Vec3f& tm) {
    unsigned c = first_child(slabs, tm);
    while (c < child) c = next_child(c, child_slabs(c, slabs, tm));  // a walk only adds bits
    return c == child;
}

/// The cell exit a hit must not lie beyond to end the ray in that cell (octree_traversal.h says
/// why it is widened by a few ulps; SlabTest::fast takes the rounded exit as it is).
template <SlabTest Slabs, class T>
T widened_cell_exit(const T& t_exit) {
    if constexpr (Slabs == SlabTest::fast)
        return t_exit;
    else
        return t_exit + Lanes<T>::abs(t_exit) * T(0x1p-21f);
}

}  // namespace trident
