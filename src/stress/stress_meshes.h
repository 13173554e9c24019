#pragma once
// The meshes of the stress cases. Closed ones come with a ball inside them to start rays from:
// a ray starting in a closed mesh must hit it, whatever its direction.
#include <cstdint>

#include "core/mesh.h"

namespace trident {

struct ClosedMesh {
    Mesh mesh;
    Vec3f interior_centre;  // every point within interior_radius of it is inside the mesh
    float interior_radius;
};

/// Geodesic unit sphere (20 f^2 triangles) with every vertex moved radially by up to +-jitter/2:
/// star-shaped about the origin, so closed and free of self-intersections.
ClosedMesh jittered_sphere(std::uint32_t frequency, float jitter, std::uint64_t seed);
/// The cube [-1, 1]^3 with each face an n x n grid of quads (two triangles each), vertices shared
/// along the cube's edges: many axis-aligned edges and vertices in few planes.
ClosedMesh tessellated_cube(std::uint32_t n);
/// scenes/closed_teapot.h's teapot; the interior ball sits in the body, away from handle and spout.
ClosedMesh closed_teapot(std::uint32_t segments);
/// scenes/asteroid.h's asteroid, star-shaped about the origin.
ClosedMesh closed_asteroid(std::uint32_t frequency, std::uint64_t seed);

/// p -> p * scale + offset for every vertex and for the interior ball (rounded to float).
ClosedMesh placed(ClosedMesh closed, float scale, const Vec3f& offset);

}  // namespace trident
