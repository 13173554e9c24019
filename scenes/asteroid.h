#pragma once
// A closed, finely tessellated object: a geodesic sphere displaced along its radii into a lumpy,
// cratered asteroid. Moving each vertex along its own direction keeps the surface star-shaped
// about the origin, so it stays watertight and free of self-intersections at any resolution.
#include <cstddef>
#include <cstdint>

#include "core/mesh.h"

namespace trident {

/// 20 * 85^2 = 144,500 triangles, the size of the reference study's Stanford Bunny.
inline constexpr std::uint32_t kAsteroidFrequency = 85;

/// The asteroid at geodesic frequency `frequency` (20 f^2 triangles, 10 f^2 + 2 vertices), about
/// 2.6 units long along x, centred on the origin. The same seed gives the same shape.
Mesh make_asteroid(std::uint32_t frequency, std::uint64_t seed);
std::size_t asteroid_triangle_count(std::uint32_t frequency);

}  // namespace trident
