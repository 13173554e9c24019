#pragma once
// Triangle mesh in structure-of-arrays form: vertex coordinates in three arrays, triangles as
// index triples in file order, optional per-vertex normals with their own index triples (OBJ
// indexes normals independently of positions).
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/aabb.h"
#include "core/ray.h"

namespace trident {

struct IndexTriple {
    std::uint32_t v0, v1, v2;
};

struct Mesh {
    std::vector<float> x, y, z;            // vertex positions
    std::vector<IndexTriple> triangles;    // triangle i = i-th face in file order
    std::vector<float> nx, ny, nz;         // per-vertex normals; empty when the mesh has none
    std::vector<IndexTriple> normal_triangles;  // per triangle, indices into nx/ny/nz; empty when none

    std::size_t vertex_count() const { return x.size(); }
    std::size_t triangle_count() const { return triangles.size(); }
    bool has_normals() const { return !normal_triangles.empty(); }

    Vec3f vertex(std::uint32_t i) const { return {x[i], y[i], z[i]}; }
    Vec3f normal(std::uint32_t i) const { return {nx[i], ny[i], nz[i]}; }
    std::uint32_t add_vertex(const Vec3f& p) {
        x.push_back(p.x); y.push_back(p.y); z.push_back(p.z);
        return static_cast<std::uint32_t>(x.size() - 1);
    }
    void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) { triangles.push_back({a, b, c}); }

    Aabb bounds() const;
    /// Appends another mesh (vertices re-indexed). Normals are kept only if both have them.
    void append(const Mesh& other);
};

/// A triangle's three corners, the form the intersection tests read.
struct Triangle {
    Vec3f a, b, c;

    Aabb bounds() const { Aabb box; box.extend(a); box.extend(b); box.extend(c); return box; }
    Vec3f centroid() const { return (a + b + c) * (1.0f / 3.0f); }
    Vec3f geometric_normal() const { return cross(b - a, c - a); }  // not normalized
};

inline Triangle triangle_of(const Mesh& mesh, std::size_t i) {
    const IndexTriple& t = mesh.triangles[i];
    return {mesh.vertex(t.v0), mesh.vertex(t.v1), mesh.vertex(t.v2)};
}

/// All triangles' corners in file order (36 bytes a triangle): what the builders start from.
std::vector<Triangle> gather_triangles(const Mesh& mesh);

}  // namespace trident
