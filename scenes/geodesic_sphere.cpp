#include "scenes/geodesic_sphere.h"

#include <array>
#include <cmath>
#include <utility>

namespace trident {

namespace {

struct Icosahedron {
    std::array<Vec3d, 12> corners;
    std::array<std::array<std::uint32_t, 3>, 20> faces;  // counter-clockwise from outside
    std::array<std::array<std::uint32_t, 2>, 30> edges;  // lower corner first
    std::array<std::array<std::uint32_t, 12>, 12> edge_of{};
};

/// The 12 corners (0, +-1, +-phi) and cyclic permutations; faces and edges are found as the
/// triples and pairs at edge length 2, so nothing is typed in by hand.
Icosahedron make_icosahedron() {
    Icosahedron ico{};
    const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
    std::uint32_t n = 0;
    for (double a : {-1.0, 1.0})
        for (double b : {-phi, phi}) {
            ico.corners[n++] = {0.0, a, b};
            ico.corners[n++] = {a, b, 0.0};
            ico.corners[n++] = {b, 0.0, a};
        }
    auto adjacent = [&](std::uint32_t i, std::uint32_t j) {
        const Vec3d d = ico.corners[i] - ico.corners[j];
        return std::abs(dot(d, d) - 4.0) < 1e-9;
    };
    std::uint32_t edge_count = 0, face_count = 0;
    for (std::uint32_t i = 0; i < 12; ++i)
        for (std::uint32_t j = i + 1; j < 12; ++j) {
            if (!adjacent(i, j)) continue;
            ico.edge_of[i][j] = ico.edge_of[j][i] = edge_count;
            ico.edges[edge_count++] = {i, j};
            for (std::uint32_t k = j + 1; k < 12; ++k) {
                if (!adjacent(i, k) || !adjacent(j, k)) continue;
                const Vec3d &a = ico.corners[i], &b = ico.corners[j], &c = ico.corners[k];
                const bool outward = dot(cross(b - a, c - a), a) > 0.0;
                ico.faces[face_count++] = outward ? std::array{i, j, k} : std::array{i, k, j};
            }
        }
    for (Vec3d& c : ico.corners) c = normalize(c);
    return ico;
}

Vec3f on_sphere(const Vec3d& p) { return Vec3f(normalize(p)); }

}  // namespace

void GeodesicSphere::emit(PartWriter& out) const {
    static const Icosahedron ico = make_icosahedron();
    const std::uint32_t f = frequency;
    const std::uint32_t first_edge_vertex = 12;
    const std::uint32_t first_face_vertex = first_edge_vertex + 30 * (f - 1);
    const std::uint32_t face_interior = (f - 1) * (f - 2) / 2;
    // Barycentric grid point (i toward corner 1, j toward corner 2) of a face -> vertex index.
    auto interior_index = [f](std::uint32_t i, std::uint32_t j) {  // i, j >= 1, i + j < f
        return (i - 1) * (f - 1) - (i - 1) * i / 2 + (j - 1);
    };
    auto vertex_id = [&](std::uint32_t face, std::uint32_t i, std::uint32_t j) -> std::uint32_t {
        const auto& c = ico.faces[face];
        const std::array<std::uint32_t, 3> w{f - i - j, i, j};
        if (w[0] == f || w[1] == f || w[2] == f) return c[w[0] == f ? 0 : (w[1] == f ? 1 : 2)];
        if (w[0] != 0 && w[1] != 0 && w[2] != 0) return first_face_vertex + face * face_interior + interior_index(i, j);
        const int zero = w[0] == 0 ? 0 : (w[1] == 0 ? 1 : 2);
        const int p = (zero + 1) % 3, q = (zero + 2) % 3;
        const std::uint32_t hi_weight = c[p] > c[q] ? w[p] : w[q];
        return first_edge_vertex + ico.edge_of[c[p]][c[q]] * (f - 1) + hi_weight - 1;
    };

    for (std::uint32_t v = 0; v < 12; ++v) out.vertex(v, Vec3f(ico.corners[v]));
    for (std::uint32_t e = 0; e < 30; ++e) {
        const Vec3d &lo = ico.corners[ico.edges[e][0]], &hi = ico.corners[ico.edges[e][1]];
        for (std::uint32_t t = 1; t < f; ++t)
            out.vertex(first_edge_vertex + e * (f - 1) + t - 1, on_sphere(lo * double(f - t) + hi * double(t)));
    }
    for (std::uint32_t face = 0; face < 20; ++face) {
        const Vec3d &a = ico.corners[ico.faces[face][0]], &b = ico.corners[ico.faces[face][1]],
                    &c = ico.corners[ico.faces[face][2]];
        for (std::uint32_t i = 1; i < f; ++i)
            for (std::uint32_t j = 1; i + j < f; ++j)
                out.vertex(first_face_vertex + face * face_interior + interior_index(i, j),
                           on_sphere(a * double(f - i - j) + b * double(i) + c * double(j)));
        for (std::uint32_t i = 0; i < f; ++i)
            for (std::uint32_t j = 0; i + j < f; ++j) {
                out.triangle(vertex_id(face, i, j), vertex_id(face, i + 1, j), vertex_id(face, i, j + 1));
                if (i + j + 2 <= f)
                    out.triangle(vertex_id(face, i + 1, j), vertex_id(face, i + 1, j + 1), vertex_id(face, i, j + 1));
            }
    }
}

}  // namespace trident
