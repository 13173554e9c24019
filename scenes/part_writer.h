#pragma once
// Where a shape writes itself: its vertices, placed, into a slice of the mesh's coordinate arrays
// and its triangles into a slice of the index array. Every part owns a slice fixed in advance, so
// parts can be written in parallel and the mesh is the same whatever the thread count.
#include <cstddef>
#include <cstdint>

#include "core/mesh.h"
#include "scenes/affine.h"

namespace trident {

class PartWriter {
public:
    PartWriter(const Affine& placement, Mesh& mesh, std::uint32_t first_vertex, std::size_t first_triangle)
        : placement_(placement), mesh_(mesh), first_vertex_(first_vertex), next_triangle_(first_triangle) {}

    /// Sets the part's vertex `local` (0-based within the part) to the placed image of `p`.
    void vertex(std::uint32_t local, const Vec3f& p) {
        const Vec3f q = placement_.apply(p);
        const std::size_t i = first_vertex_ + local;
        mesh_.x[i] = q.x;
        mesh_.y[i] = q.y;
        mesh_.z[i] = q.z;
    }
    /// Appends a triangle of local vertex indices, counter-clockwise seen from outside.
    void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        mesh_.triangles[next_triangle_++] = {first_vertex_ + a, first_vertex_ + b, first_vertex_ + c};
    }
    std::size_t next_triangle() const { return next_triangle_; }

private:
    Affine placement_;
    Mesh& mesh_;
    std::uint32_t first_vertex_;
    std::size_t next_triangle_;
};

}  // namespace trident
