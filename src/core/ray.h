#pragma once
// A single ray and the result of tracing it.
#include <cstdint>
#include <limits>

#include "core/vec3.h"

namespace trident {

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

struct Ray {
    Vec3f origin;
    Vec3f dir;  // need not be normalized; t is measured in units of |dir|
    float tmin = 0.0f;
    float tmax = kInfinity;
};

/// Index of a triangle in the scene's file order (the hit buffer's numbering).
using TriangleId = std::uint32_t;
inline constexpr TriangleId kNoTriangle = 0xFFFFFFFFu;

/// Closest (or any) hit: the triangle in file order, the distance, and the barycentrics of the
/// hit point (u weighs vertex 1, v weighs vertex 2).
struct Hit {
    TriangleId triangle = kNoTriangle;
    float t = kInfinity;
    float u = 0.0f;
    float v = 0.0f;

    bool is_hit() const { return triangle != kNoTriangle; }
};

}  // namespace trident
