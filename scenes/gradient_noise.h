#pragma once
// Deterministic 3D gradient noise (Perlin, "Improving Noise", SIGGRAPH 2002: quintic fade, the 12
// cube-edge gradients) with the permutation table replaced by a splitmix64 hash of the lattice
// point, so the field depends only on the seed and is the same on every platform.
#include <cstdint>

#include "core/vec3.h"

namespace trident {

/// Smooth noise in roughly [-1, 1], zero on the integer lattice.
float gradient_noise(const Vec3f& p, std::uint64_t seed);

/// Fractional Brownian motion: `octaves` layers of gradient noise, each at twice the frequency
/// and half the amplitude of the one before, normalized so the amplitudes sum to 1.
float fractal_noise(const Vec3f& p, int octaves, std::uint64_t seed);

}  // namespace trident
