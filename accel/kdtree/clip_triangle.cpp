#include "accel/kdtree/clip_triangle.h"

#include <cmath>
#include <limits>
#include <utility>

namespace trident::kd {

namespace {

// Rounding to the nearest float, then one step outward when that crossed the exact value. The
// clipped corners carry a relative error near 1e-16 (one division and one product in double),
// far below a float step, so the rounded bounds hold the exact clipped triangle except within
// that error of a float value; vertices that are not clipped stay exact.
float round_down(double d) {
    const float f = float(d);
    return double(f) > d ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float round_up(double d) {
    const float f = float(d);
    return double(f) < d ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

}  // namespace

std::optional<Aabb> clipped_triangle_bounds(const Triangle& tri, const Aabb& box) {
    constexpr int kMaxCorners = 9;  // each of the six planes adds at most one corner to the three
    Vec3d buffers[2][kMaxCorners] = {{Vec3d(tri.a), Vec3d(tri.b), Vec3d(tri.c)}, {}};
    Vec3d* polygon = buffers[0];
    Vec3d* clipped = buffers[1];
    int count = 3;
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            const double plane = side == 0 ? box.lo[axis] : box.hi[axis];
            const double sign = side == 0 ? 1.0 : -1.0;  // inside: sign * (x - plane) >= 0
            auto inside = [&](const Vec3d& p) { return sign * (p[axis] - plane) >= 0.0; };
            bool all_inside = true;
            for (int i = 0; i < count; ++i) all_inside = all_inside && inside(polygon[i]);
            if (all_inside) continue;
            int kept = 0;
            for (int i = 0; i < count; ++i) {
                const Vec3d& from = polygon[i == 0 ? count - 1 : i - 1];
                const Vec3d& to = polygon[i];
                if (inside(from) != inside(to)) {
                    const double s = (plane - from[axis]) / (to[axis] - from[axis]);
                    Vec3d crossing = from + (to - from) * s;
                    crossing[axis] = plane;  // exactly on the plane, whatever the rounding of s
                    clipped[kept++] = crossing;
                }
                if (inside(to)) clipped[kept++] = to;
            }
            count = kept;
            if (count == 0) return std::nullopt;
            std::swap(polygon, clipped);
        }
    }
    Vec3d lo = polygon[0], hi = polygon[0];
    for (int i = 1; i < count; ++i) {
        lo = min(lo, polygon[i]);
        hi = max(hi, polygon[i]);
    }
    Aabb bounds;
    for (int axis = 0; axis < 3; ++axis) {
        bounds.lo[axis] = std::max(round_down(lo[axis]), box.lo[axis]);
        bounds.hi[axis] = std::min(round_up(hi[axis]), box.hi[axis]);
    }
    return bounds;
}

}  // namespace trident::kd
