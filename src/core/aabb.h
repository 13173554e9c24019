#pragma once
// Axis-aligned bounding box in single precision. An empty box has lo = +inf, hi = -inf so that
// extending it by anything yields that thing.
#include <limits>

#include "core/vec3.h"

namespace trident {

struct Aabb {
    Vec3f lo{std::numeric_limits<float>::infinity()};
    Vec3f hi{-std::numeric_limits<float>::infinity()};

    void extend(const Vec3f& p) { lo = min(lo, p); hi = max(hi, p); }
    void extend(const Aabb& b) { lo = min(lo, b.lo); hi = max(hi, b.hi); }

    bool is_empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    Vec3f extent() const { return hi - lo; }
    Vec3f center() const { return (lo + hi) * 0.5f; }
    /// Surface area; 0 for an empty box (so empty sides cost nothing in an SAH).
    float surface_area() const {
        if (is_empty()) return 0.0f;
        const Vec3f e = extent();
        return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
    }
    int largest_axis() const { return largest_abs_axis(extent()); }
    bool contains(const Aabb& b) const {
        return lo.x <= b.lo.x && lo.y <= b.lo.y && lo.z <= b.lo.z && hi.x >= b.hi.x && hi.y >= b.hi.y && hi.z >= b.hi.z;
    }
    bool contains(const Vec3f& p) const {
        return lo.x <= p.x && lo.y <= p.y && lo.z <= p.z && hi.x >= p.x && hi.y >= p.y && hi.z >= p.z;
    }
};

inline Aabb merge(Aabb a, const Aabb& b) { a.extend(b); return a; }

/// Surface area in double, for costs summed over a tree: a float area overflows for boxes wider
/// than about 1e19. 0 for an empty box.
inline double surface_area_in_double(const Aabb& box) {
    if (box.is_empty()) return 0.0;
    const double x = double(box.hi.x) - box.lo.x, y = double(box.hi.y) - box.lo.y, z = double(box.hi.z) - box.lo.z;
    return 2.0 * (x * y + y * z + z * x);
}

}  // namespace trident
