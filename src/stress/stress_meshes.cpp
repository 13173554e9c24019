#include "stress/stress_meshes.h"

#include "scenes/asteroid.h"
#include "scenes/closed_teapot.h"
#include "scenes/hash_random.h"
#include "scenes/mesh_builder.h"

namespace trident {

ClosedMesh jittered_sphere(std::uint32_t frequency, float jitter, std::uint64_t seed) {
    MeshBuilder builder;
    builder.add(GeodesicSphere{frequency});
    Mesh mesh = builder.build();
    HashRandom random(seed);
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
        const float radius = 1.0f + jitter * (random.uniform() - 0.5f);
        mesh.x[i] *= radius, mesh.y[i] *= radius, mesh.z[i] *= radius;
    }
    return {std::move(mesh), Vec3f(0.0f), 0.5f};
}

ClosedMesh tessellated_cube(std::uint32_t n) {
    // Vertices live on the lattice {0..n}^3; index_of maps a lattice point to its vertex once.
    const std::uint32_t side = n + 1;
    std::vector<std::uint32_t> index_of(std::size_t(side) * side * side, 0xFFFFFFFFu);
    Mesh mesh;
    auto vertex = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
        std::uint32_t& slot = index_of[(std::size_t(i) * side + j) * side + k];
        if (slot == 0xFFFFFFFFu) {
            auto coord = [&](std::uint32_t c) { return -1.0f + 2.0f * float(c) / float(n); };
            slot = mesh.add_vertex({coord(i), coord(j), coord(k)});
        }
        return slot;
    };
    for (int axis = 0; axis < 3; ++axis) {
        for (std::uint32_t face = 0; face < 2; ++face) {
            const std::uint32_t level = face * n;
            for (std::uint32_t a = 0; a < n; ++a) {
                for (std::uint32_t b = 0; b < n; ++b) {
                    auto corner = [&](std::uint32_t da, std::uint32_t db) {
                        std::uint32_t c[3];
                        c[axis] = level;
                        c[(axis + 1) % 3] = a + da;
                        c[(axis + 2) % 3] = b + db;
                        return vertex(c[0], c[1], c[2]);
                    };
                    const std::uint32_t v00 = corner(0, 0), v10 = corner(1, 0), v01 = corner(0, 1),
                                        v11 = corner(1, 1);
                    if (face == 1) {  // outward winding on the high face, reversed on the low one
                        mesh.add_triangle(v00, v10, v11);
                        mesh.add_triangle(v00, v11, v01);
                    } else {
                        mesh.add_triangle(v00, v11, v10);
                        mesh.add_triangle(v00, v01, v11);
                    }
                }
            }
        }
    }
    return {std::move(mesh), Vec3f(0.0f), 0.9f};
}

ClosedMesh closed_teapot(std::uint32_t segments) {
    // The body's radius exceeds 1.5 from height 0.15 to 2.4; handle and spout start beyond x = +-1.1.
    return {make_closed_teapot_like_mesh(segments), Vec3f(0.0f, 1.2f, 0.0f), 0.6f};
}

ClosedMesh closed_asteroid(std::uint32_t frequency, std::uint64_t seed) {
    return {make_asteroid(frequency, seed), Vec3f(0.0f), 0.3f};
}

ClosedMesh placed(ClosedMesh closed, float scale, const Vec3f& offset) {
    Mesh& mesh = closed.mesh;
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
        mesh.x[i] = mesh.x[i] * scale + offset.x;
        mesh.y[i] = mesh.y[i] * scale + offset.y;
        mesh.z[i] = mesh.z[i] * scale + offset.z;
    }
    closed.interior_centre = closed.interior_centre * scale + offset;
    closed.interior_radius *= scale;
    return closed;
}

}  // namespace trident
