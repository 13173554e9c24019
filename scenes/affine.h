#pragma once
// Placement of a part in a scene: a linear map (three column axes) and a translation.
#include <cmath>
#include <numbers>

#include "core/vec3.h"

namespace trident {

/// The scenes' angles are in radians.
inline constexpr float kPi = std::numbers::pi_v<float>;

struct Affine {
    Vec3f x_axis{1.0f, 0.0f, 0.0f};
    Vec3f y_axis{0.0f, 1.0f, 0.0f};
    Vec3f z_axis{0.0f, 0.0f, 1.0f};
    Vec3f origin{0.0f, 0.0f, 0.0f};

    Vec3f apply_linear(const Vec3f& v) const { return x_axis * v.x + y_axis * v.y + z_axis * v.z; }
    Vec3f apply(const Vec3f& p) const { return apply_linear(p) + origin; }
    /// Positive for a placement that keeps triangle winding (no mirroring, no collapse).
    float determinant() const { return dot(x_axis, cross(y_axis, z_axis)); }
};

/// outer * inner applies inner first.
inline Affine operator*(const Affine& outer, const Affine& inner) {
    return {outer.apply_linear(inner.x_axis), outer.apply_linear(inner.y_axis), outer.apply_linear(inner.z_axis),
            outer.apply(inner.origin)};
}

inline Affine translation(const Vec3f& offset) { return {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, offset}; }
inline Affine scaling(const Vec3f& factors) { return {{factors.x, 0, 0}, {0, factors.y, 0}, {0, 0, factors.z}, {}}; }
inline Affine rotation_x(float radians) {
    const float c = std::cos(radians), s = std::sin(radians);
    return {{1, 0, 0}, {0, c, s}, {0, -s, c}, {}};
}
inline Affine rotation_y(float radians) {
    const float c = std::cos(radians), s = std::sin(radians);
    return {{c, 0, -s}, {0, 1, 0}, {s, 0, c}, {}};
}
inline Affine rotation_z(float radians) {
    const float c = std::cos(radians), s = std::sin(radians);
    return {{c, s, 0}, {-s, c, 0}, {0, 0, 1}, {}};
}

/// A rotation taking the y axis to the direction of `direction` (any non-zero vector).
inline Affine y_along(const Vec3f& direction) {
    const Vec3f y = normalize(direction);
    const Vec3f helper = std::abs(y.x) < 0.9f ? Vec3f{1.0f, 0.0f, 0.0f} : Vec3f{0.0f, 0.0f, 1.0f};
    const Vec3f x = normalize(cross(y, helper));
    return {x, y, cross(x, y), {}};
}

}  // namespace trident
