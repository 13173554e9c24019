#pragma once
// The bounds of the part of a triangle inside a box: what Havran's "perfect splits" (Havran,
// "Heuristic Ray Shooting Algorithms", PhD thesis, 2000, section 4.5) give the kd-tree builder for
// a triangle straddling a split plane, so that each child sees tight bounds and a child the
// triangle misses drops it.
#include <optional>

#include "core/aabb.h"
#include "core/mesh.h"

namespace trident::kd {

/// Sutherland-Hodgman clipping of the triangle against the six planes of the closed box, in
/// double; nullopt when nothing is left (a triangle that only touches the box keeps the touching
/// point or edge). The bounds are rounded outward to float and lie inside the box.
std::optional<Aabb> clipped_triangle_bounds(const Triangle& tri, const Aabb& box);

}  // namespace trident::kd
