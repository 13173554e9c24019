#pragma once
// Reproducible cosine-distributed directions for ambient-occlusion and diffuse-bounce rays.
// Each (pixel, sample) pair draws its numbers from a counter-based hash rather than a stateful
// generator (Salmon et al., "Parallel Random Numbers: As Easy as 1, 2, 3", SC 2011), so the
// directions do not depend on thread count, tile order or packet grouping.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "core/vec3.h"

namespace trident {

/// SplitMix64's output mix (Steele, Lea and Flood, "Fast Splittable Pseudorandom Number
/// Generators", OOPSLA 2014): a bijective 64-bit avalanche, good enough for sampling.
constexpr std::uint64_t mix64(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/// Two numbers in [0, 1) for sample `sample` of pixel `pixel` under `seed`.
struct UniformPair {
    float u1, u2;
};
constexpr UniformPair sample_uniforms(std::uint64_t pixel, std::uint32_t sample, std::uint64_t seed = 0) {
    const std::uint64_t bits = mix64(mix64(seed ^ 0x9e3779b97f4a7c15ULL) ^ (pixel << 24) ^ sample);
    constexpr float kScale = 1.0f / 16777216.0f;  // 24 bits: every value exact in a float
    return {float(bits >> 40) * kScale, float((bits >> 16) & 0xFFFFFFu) * kScale};
}

/// Two unit vectors completing n (unit) to a right-handed frame, without branches on a
/// threshold: Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 6(1), 2017.
struct Frame {
    Vec3f tangent, bitangent, normal;
};
inline Frame frame_around(const Vec3f& n) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    return {Vec3f{1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x}, Vec3f{b, sign + n.y * n.y * a, -n.y}, n};
}

/// A direction about unit n with density cos(theta) / pi: a uniform point on the unit disc lifted
/// to the hemisphere (Malley's method; Pharr, Jakob and Humphreys, PBRT 4th ed., 13.6.3).
inline Vec3f cosine_direction(const Vec3f& n, UniformPair u) {
    const float r = std::sqrt(u.u1);
    const float phi = 2.0f * std::numbers::pi_v<float> * u.u2;
    const float z = std::sqrt(std::max(0.0f, 1.0f - u.u1));
    const Frame f = frame_around(n);
    return normalize(f.tangent * (r * std::cos(phi)) + f.bitangent * (r * std::sin(phi)) + f.normal * z);
}

}  // namespace trident
