#include "scenes/mesh_builder.h"

#include <limits>
#include <stdexcept>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace trident {

void MeshBuilder::add(Shape shape, const Affine& placement) {
    if (!(placement.determinant() > 0.0f))
        throw std::invalid_argument("MeshBuilder::add: placement must keep orientation");
    const auto [vertices, triangles] = std::visit(
        [](const auto& s) {
            return std::pair{std::size_t(s.vertex_count()), s.triangle_count()};
        },
        shape);
    if (vertex_count_ + vertices > std::numeric_limits<std::uint32_t>::max())
        throw std::length_error("MeshBuilder::add: more vertices than 32-bit indices can address");
    parts_.push_back({std::move(shape), placement, std::uint32_t(vertex_count_), triangle_count_});
    vertex_count_ += vertices;
    triangle_count_ += triangles;
}

Mesh MeshBuilder::build() const {
    Mesh mesh;
    mesh.x.resize(vertex_count_);
    mesh.y.resize(vertex_count_);
    mesh.z.resize(vertex_count_);
    mesh.triangles.resize(triangle_count_);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, parts_.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t i = range.begin(); i != range.end(); ++i) {
                              const Part& part = parts_[i];
                              PartWriter writer(part.placement, mesh, part.first_vertex, part.first_triangle);
                              std::visit([&](const auto& s) { s.emit(writer); }, part.shape);
                          }
                      });
    return mesh;
}

}  // namespace trident
