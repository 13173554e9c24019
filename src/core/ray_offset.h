#pragma once
// Moving a secondary ray's origin off the surface it starts on, robustly at any scale: Wächter and
// Binder, "A Fast and Robust Method for Avoiding Self-Intersection" (Ray Tracing Gems, ch. 6).
// The point is pushed along the geometric normal by a few ulps of its own coordinates (integer
// offsets on the float bit patterns), plus a tiny absolute offset near the origin where ulps vanish.
#include <bit>
#include <cmath>
#include <cstdint>

#include "core/vec3.h"

namespace trident {

inline Vec3f offset_ray_origin(const Vec3f& p, const Vec3f& n) {
    constexpr float kOrigin = 1.0f / 32.0f, kFloatScale = 1.0f / 65536.0f, kIntScale = 256.0f;
    Vec3f out;
    for (int axis = 0; axis < 3; ++axis) {
        const auto step = std::int32_t(kIntScale * n[axis]);
        const auto bits = std::bit_cast<std::int32_t>(p[axis]);
        const float shifted = std::bit_cast<float>(bits + (p[axis] < 0.0f ? -step : step));
        out[axis] = std::abs(p[axis]) < kOrigin ? p[axis] + kFloatScale * n[axis] : shifted;
    }
    return out;
}

}  // namespace trident
