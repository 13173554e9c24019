#pragma once
// Triangle/box overlap decided by clipping, an algorithm independent of the separating-axis test
// the octree builder uses (core/triangle_box_overlap.h), for the tests of both.
#include <vector>

#include "core/mesh.h"
#include "core/vec3.h"

namespace trident::testing {

/// Does the triangle meet the closed box [lo, hi]? Clips the triangle (Sutherland-Hodgman) against
/// the six faces in double; touching counts.
inline bool triangle_meets_box_by_clipping(const Triangle& tri, const Vec3d& lo, const Vec3d& hi) {
    std::vector<Vec3d> polygon{Vec3d(tri.a), Vec3d(tri.b), Vec3d(tri.c)}, next;
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            const double bound = side == 0 ? lo[axis] : hi[axis];
            auto inside = [&](const Vec3d& p) { return side == 0 ? p[axis] >= bound : p[axis] <= bound; };
            next.clear();
            for (std::size_t i = 0; i < polygon.size(); ++i) {
                const Vec3d& p = polygon[i];
                const Vec3d& q = polygon[(i + 1) % polygon.size()];
                if (inside(p)) next.push_back(p);
                if (inside(p) != inside(q)) {
                    const double t = (bound - p[axis]) / (q[axis] - p[axis]);
                    Vec3d x = p + (q - p) * t;
                    x[axis] = bound;
                    next.push_back(x);
                }
            }
            polygon.swap(next);
            if (polygon.empty()) return false;
        }
    }
    return true;
}

}  // namespace trident::testing
