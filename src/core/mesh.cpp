#include "core/mesh.h"

namespace trident {

Aabb Mesh::bounds() const {
    Aabb box;
    for (std::size_t i = 0; i < x.size(); ++i) box.extend(Vec3f{x[i], y[i], z[i]});
    return box;
}

void Mesh::append(const Mesh& other) {
    const auto base = static_cast<std::uint32_t>(vertex_count());
    const auto normal_base = static_cast<std::uint32_t>(nx.size());
    const bool keep_normals = (has_normals() || triangles.empty()) && other.has_normals();
    x.insert(x.end(), other.x.begin(), other.x.end());
    y.insert(y.end(), other.y.begin(), other.y.end());
    z.insert(z.end(), other.z.begin(), other.z.end());
    for (const IndexTriple& t : other.triangles) triangles.push_back({t.v0 + base, t.v1 + base, t.v2 + base});
    if (keep_normals) {
        nx.insert(nx.end(), other.nx.begin(), other.nx.end());
        ny.insert(ny.end(), other.ny.begin(), other.ny.end());
        nz.insert(nz.end(), other.nz.begin(), other.nz.end());
        for (const IndexTriple& t : other.normal_triangles)
            normal_triangles.push_back({t.v0 + normal_base, t.v1 + normal_base, t.v2 + normal_base});
    } else {
        nx.clear(); ny.clear(); nz.clear();
        normal_triangles.clear();
    }
}

std::vector<Triangle> gather_triangles(const Mesh& mesh) {
    std::vector<Triangle> out(mesh.triangle_count());
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = triangle_of(mesh, i);
    return out;
}

}  // namespace trident
