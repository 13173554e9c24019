#pragma once
// The double-precision reference: the watertight test evaluated in double over every triangle.
// Slow by design (it is what every structure is checked against in tests); ties in t go to the
// lower triangle index so the reference is deterministic.
#include <limits>
#include <span>

#include "core/mesh.h"
#include "core/ray.h"

namespace trident {

struct ReferenceHit {
    TriangleId triangle = kNoTriangle;
    double t = std::numeric_limits<double>::infinity();
    bool is_hit() const { return triangle != kNoTriangle; }
};

/// Watertight test in double; returns t or +inf for a miss (ray.tmin <= t < ray.tmax).
double intersect_reference(const Ray& ray, const Triangle& tri);

ReferenceHit trace_reference(std::span<const Triangle> triangles, const Ray& ray);

/// Any triangle with ray.tmin <= t < ray.tmax.
bool occluded_reference(std::span<const Triangle> triangles, const Ray& ray);

}  // namespace trident
