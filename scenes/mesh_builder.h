#pragma once
// A scene as a list of placed parts. The list is cheap to make, so a scene's triangle count is
// known without generating it; build() then gives every part a fixed slice of the mesh and writes
// the parts in parallel, so the mesh is identical whatever the thread count.
#include <cstddef>
#include <cstdint>
#include <variant>
#include <vector>

#include "core/mesh.h"
#include "scenes/affine.h"
#include "scenes/geodesic_sphere.h"
#include "scenes/primitives.h"

namespace trident {

using Shape = std::variant<Box, Lathe, Arch, GeodesicSphere>;

class MeshBuilder {
public:
    /// Adds a part; throws std::invalid_argument if the placement mirrors or collapses it (that
    /// would flip its winding or make zero-area triangles).
    void add(Shape shape, const Affine& placement = {});

    std::size_t part_count() const { return parts_.size(); }
    std::size_t vertex_count() const { return vertex_count_; }
    std::size_t triangle_count() const { return triangle_count_; }
    Mesh build() const;

private:
    struct Part {
        Shape shape;
        Affine placement;
        std::uint32_t first_vertex;
        std::size_t first_triangle;
    };
    std::vector<Part> parts_;
    std::size_t vertex_count_ = 0;
    std::size_t triangle_count_ = 0;
};

}  // namespace trident
