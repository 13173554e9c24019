#pragma once
// Meshes that stress the octree: a flat grid, triangles collapsed to one point, a fan around one
// point, a soup far from the origin.
#include <cstdint>
#include <random>

#include "core/mesh.h"

namespace trident::testing {

/// `cells` x `cells` squares (two triangles each) covering [0, size]^2 in the plane z = height.
inline Mesh flat_grid(int cells, float size = 1.0f, float height = 0.5f) {
    Mesh mesh;
    const float step = size / float(cells);
    for (int j = 0; j <= cells; ++j)
        for (int i = 0; i <= cells; ++i) mesh.add_vertex({float(i) * step, float(j) * step, height});
    const auto at = [&](int i, int j) { return std::uint32_t(j * (cells + 1) + i); };
    for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i) {
            mesh.add_triangle(at(i, j), at(i + 1, j), at(i + 1, j + 1));
            mesh.add_triangle(at(i, j), at(i + 1, j + 1), at(i, j + 1));
        }
    return mesh;
}

/// `count` triangles whose three corners are all `point`.
inline Mesh collapsed_to_point(std::size_t count, const Vec3f& point) {
    Mesh mesh;
    const auto v = mesh.add_vertex(point);
    for (std::size_t i = 0; i < count; ++i) mesh.add_triangle(v, v, v);
    return mesh;
}

/// `count` triangles sharing the corner `hub`, their other corners random in [-1, 1]^3.
inline Mesh fan_around(std::size_t count, const Vec3f& hub, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> coordinate(-1.0f, 1.0f);
    Mesh mesh;
    const auto h = mesh.add_vertex(hub);
    for (std::size_t i = 0; i < count; ++i) {
        const auto a = mesh.add_vertex({coordinate(rng), coordinate(rng), coordinate(rng)});
        const auto b = mesh.add_vertex({coordinate(rng), coordinate(rng), coordinate(rng)});
        mesh.add_triangle(h, a, b);
    }
    return mesh;
}

inline Mesh translated(Mesh mesh, const Vec3f& offset) {
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
        mesh.x[i] += offset.x;
        mesh.y[i] += offset.y;
        mesh.z[i] += offset.z;
    }
    return mesh;
}

}  // namespace trident::testing
