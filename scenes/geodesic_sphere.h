#pragma once
// The unit sphere as a class-I geodesic polyhedron: each icosahedron face split into
// frequency^2 triangles, points pushed out to the sphere. Vertices on shared icosahedron edges
// and corners are written once, so the mesh is closed and consistently wound by construction:
// 10 f^2 + 2 vertices, 20 f^2 triangles. Unlike repeated 4-way subdivision, any frequency works,
// so the triangle count can be chosen finely.
#include <cstddef>
#include <cstdint>

#include "scenes/part_writer.h"

namespace trident {

struct GeodesicSphere {
    std::uint32_t frequency = 8;

    std::uint32_t vertex_count() const { return 10 * frequency * frequency + 2; }
    std::size_t triangle_count() const { return 20 * std::size_t(frequency) * frequency; }
    void emit(PartWriter& out) const;
};

}  // namespace trident
