#pragma once
// Topology and geometry checks on meshes for the scene tests: edges after welding positions,
// zero-area triangles, enclosed volume.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "core/mesh.h"

namespace trident::testing {

/// Vertex ids after welding identical positions (-0 and +0 are one position).
inline std::vector<std::uint32_t> welded_ids(const Mesh& mesh, std::size_t* distinct_positions = nullptr) {
    std::map<std::array<std::uint32_t, 3>, std::uint32_t> ids;
    std::vector<std::uint32_t> out(mesh.vertex_count());
    for (std::uint32_t i = 0; i < mesh.vertex_count(); ++i) {
        const Vec3f p = mesh.vertex(i) + Vec3f(0.0f);
        const std::array key{std::bit_cast<std::uint32_t>(p.x), std::bit_cast<std::uint32_t>(p.y),
                             std::bit_cast<std::uint32_t>(p.z)};
        out[i] = ids.try_emplace(key, std::uint32_t(ids.size())).first->second;
    }
    if (distinct_positions) *distinct_positions = ids.size();
    return out;
}

struct EdgeTopology {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> open_edges;  // mesh vertex ids, used by one triangle
    std::size_t non_manifold_edges = 0;       // undirected edges used by more than two triangles
    std::size_t repeated_directed_edges = 0;  // directed edges used twice: neighbours wound oppositely
    std::size_t edges = 0;

    bool closed_and_consistent() const {
        return open_edges.empty() && non_manifold_edges == 0 && repeated_directed_edges == 0;
    }
};

inline EdgeTopology edge_topology(const Mesh& mesh) {
    const std::vector<std::uint32_t> id = welded_ids(mesh);
    struct Use {
        std::uint32_t count = 0, forward = 0, mesh_a = 0, mesh_b = 0;
    };
    std::map<std::pair<std::uint32_t, std::uint32_t>, Use> uses;
    for (const IndexTriple& t : mesh.triangles) {
        const std::array<std::uint32_t, 3> v{t.v0, t.v1, t.v2};
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = v[k], b = v[(k + 1) % 3];
            const std::uint32_t ia = id[a], ib = id[b];
            Use& u = uses[{std::min(ia, ib), std::max(ia, ib)}];
            ++u.count;
            u.forward += ia < ib ? 1 : 0;
            u.mesh_a = a;
            u.mesh_b = b;
        }
    }
    EdgeTopology out;
    out.edges = uses.size();
    for (const auto& [key, u] : uses) {
        if (u.count == 1) out.open_edges.push_back({u.mesh_a, u.mesh_b});
        if (u.count > 2) ++out.non_manifold_edges;
        if (u.count == 2 && u.forward != 1) ++out.repeated_directed_edges;
    }
    return out;
}

/// Triangles whose area is zero in float (the cross product the tracers see) or in double.
inline std::size_t zero_area_triangles(const Mesh& mesh) {
    std::size_t count = 0;
    for (std::size_t i = 0; i < mesh.triangle_count(); ++i) {
        const Triangle t = triangle_of(mesh, i);
        const Vec3f n = t.geometric_normal();
        const Vec3d nd = cross(Vec3d(t.b) - Vec3d(t.a), Vec3d(t.c) - Vec3d(t.a));
        if (dot(n, n) == 0.0f || dot(nd, nd) == 0.0) ++count;
    }
    return count;
}

/// Signed enclosed volume (divergence theorem); positive for a closed mesh wound outwards.
inline double signed_volume(const Mesh& mesh) {
    double v = 0.0;
    for (std::size_t i = 0; i < mesh.triangle_count(); ++i) {
        const Triangle t = triangle_of(mesh, i);
        v += dot(Vec3d(t.a), cross(Vec3d(t.b), Vec3d(t.c))) / 6.0;
    }
    return v;
}

inline bool all_finite(const Mesh& mesh) {
    for (std::uint32_t i = 0; i < mesh.vertex_count(); ++i)
        if (!is_finite(mesh.vertex(i))) return false;
    return true;
}

/// Bit-identical positions and identical triangles.
inline bool identical(const Mesh& a, const Mesh& b) {
    auto same_bits = [](const std::vector<float>& s, const std::vector<float>& t) {
        return std::equal(s.begin(), s.end(), t.begin(), t.end(), [](float u, float v) {
            return std::bit_cast<std::uint32_t>(u) == std::bit_cast<std::uint32_t>(v);
        });
    };
    const bool same_triangles = std::equal(
        a.triangles.begin(), a.triangles.end(), b.triangles.begin(), b.triangles.end(),
        [](const IndexTriple& s, const IndexTriple& t) { return s.v0 == t.v0 && s.v1 == t.v1 && s.v2 == t.v2; });
    return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z) && same_triangles;
}

}  // namespace trident::testing
