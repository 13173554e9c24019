#pragma once
// Triangle/box overlap by the separating axis theorem (Akenine-Möller, "Fast 3D Triangle-Box
// Overlap Testing", JGT 6(1), 2001): a triangle and a box are disjoint iff one of 13 axes
// separates their projections (the 3 box normals, the triangle normal, and the 9 cross products
// of a box normal with a triangle edge). Written over the value type so the octree builder runs it
// in float and its tests in double. Touching counts as overlapping.
#include <algorithm>
#include <cmath>

#include "core/vec3.h"

namespace trident {

namespace detail {

/// True when the projections of the triangle (p0, p1, p2) and of the box ([-r, r]) on one axis
/// do not meet.
template <class T>
bool separated_on_axis(T p0, T p1, T p2, T r) {
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
}

}  // namespace detail

/// Does the triangle (a, b, c) meet the box centred at `centre` with half-extents `half`?
template <class T>
bool triangle_overlaps_box(const Vec3T<T>& a, const Vec3T<T>& b, const Vec3T<T>& c, const Vec3T<T>& centre,
                           const Vec3T<T>& half) {
    using detail::separated_on_axis;
    // Work relative to the box centre: smaller magnitudes, smaller rounding errors.
    const Vec3T<T> v0 = a - centre, v1 = b - centre, v2 = c - centre;

    // The box normals: the triangle's bounding box against the box.
    for (int axis = 0; axis < 3; ++axis)
        if (separated_on_axis(v0[axis], v1[axis], v2[axis], half[axis])) return false;

    // The triangle's plane n . x = n . v0 against the box's projection [-r, r] on n; tested before
    // the edge axes because it rejects most boxes near a large triangle. A degenerate triangle
    // has n = 0 and is left to the edge axes.
    const Vec3T<T> edges[3] = {v1 - v0, v2 - v1, v0 - v2};
    const Vec3T<T> n = cross(edges[0], edges[1]);
    const T r = half.x * std::abs(n.x) + half.y * std::abs(n.y) + half.z * std::abs(n.z);
    if (std::abs(dot(n, v0)) > r) return false;

    // The nine edge axes e_i x edge. For x x e = (0, -e.z, e.y) the projection of v is
    // e.y v.z - e.z v.y and the box's radius is half.y |e.z| + half.z |e.y|; y and z likewise.
    for (const Vec3T<T>& e : edges) {
        const T ax = std::abs(e.x), ay = std::abs(e.y), az = std::abs(e.z);
        if (separated_on_axis(e.y * v0.z - e.z * v0.y, e.y * v1.z - e.z * v1.y, e.y * v2.z - e.z * v2.y,
                              half.y * az + half.z * ay))
            return false;
        if (separated_on_axis(e.z * v0.x - e.x * v0.z, e.z * v1.x - e.x * v1.z, e.z * v2.x - e.x * v2.z,
                              half.x * az + half.z * ax))
            return false;
        if (separated_on_axis(e.x * v0.y - e.y * v0.x, e.x * v1.y - e.y * v1.x, e.x * v2.y - e.y * v2.x,
                              half.x * ay + half.y * ax))
            return false;
    }
    return true;
}

}  // namespace trident
