#pragma once
// Random triangle soups and rays for property tests, deterministic by seed.
#include <cmath>
#include <random>
#include <vector>

#include "core/mesh.h"
#include "core/ray.h"

namespace trident::testing {

/// `count` triangles with corners in [-1, 1]^3 around random centres; `size` scales each triangle.
inline Mesh random_soup(std::size_t count, std::uint32_t seed, float size = 0.2f) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> centre(-1.0f, 1.0f), offset(-size, size);
    Mesh mesh;
    for (std::size_t i = 0; i < count; ++i) {
        const Vec3f c{centre(rng), centre(rng), centre(rng)};
        const auto a = mesh.add_vertex(c + Vec3f{offset(rng), offset(rng), offset(rng)});
        const auto b = mesh.add_vertex(c + Vec3f{offset(rng), offset(rng), offset(rng)});
        const auto d = mesh.add_vertex(c + Vec3f{offset(rng), offset(rng), offset(rng)});
        mesh.add_triangle(a, b, d);
    }
    return mesh;
}

/// random_soup's small triangles with `large` triangles across the whole box among them (the
/// walls and beams of an architectural scene): an object split leaves a large triangle's box over
/// one child's small ones, a spatial split cuts it so that both children stay tight.
inline Mesh soup_with_large_triangles(std::size_t count, std::size_t large, std::uint32_t seed) {
    Mesh mesh = random_soup(count, seed, 0.05f);
    std::mt19937 rng(seed + 1);
    std::uniform_real_distribution<float> corner(-1.0f, 1.0f);
    for (std::size_t i = 0; i < large; ++i) {
        const Vec3f a{corner(rng), -1.0f, corner(rng)}, b{corner(rng), 1.0f, corner(rng)};
        const Vec3f c{-a.x, corner(rng), -b.z};
        mesh.add_triangle(mesh.add_vertex(a), mesh.add_vertex(b), mesh.add_vertex(c));
    }
    return mesh;
}

/// Rays from a sphere of radius `radius` around the box centre towards random points inside the
/// box; every `axis_every`-th ray is axis-parallel (with +0 and -0 in the other components).
inline std::vector<Ray> random_rays(const Aabb& box, std::size_t count, std::uint32_t seed, int axis_every = 5) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), sym(-1.0f, 1.0f);
    const Vec3f centre = box.center(), extent = box.extent();
    const float radius = length(extent) + 1e-3f;
    std::vector<Ray> rays;
    rays.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        const Vec3f target = box.lo + Vec3f{unit(rng) * extent.x, unit(rng) * extent.y, unit(rng) * extent.z};
        Ray ray;
        if (axis_every > 0 && i % std::size_t(axis_every) == 0) {
            const int axis = int(i / std::size_t(axis_every)) % 3;
            const float sign = (i / std::size_t(3 * axis_every)) % 2 ? -1.0f : 1.0f;
            const float zero = (i / std::size_t(6 * axis_every)) % 2 ? -0.0f : 0.0f;
            ray.dir = Vec3f{zero, zero, zero};
            ray.dir[axis] = sign;
            ray.origin = target;
            ray.origin[axis] = centre[axis] - sign * radius;
        } else {
            Vec3f d{sym(rng), sym(rng), sym(rng)};
            if (dot(d, d) < 1e-6f) d = {1.0f, 0.0f, 0.0f};
            d = normalize(d);
            ray.origin = target - d * radius;
            ray.dir = d;
        }
        rays.push_back(ray);
    }
    return rays;
}

/// Rays from `origin` whose direction components take every sign, +0 and -0 included, cycling so
/// that each packet holds lanes of several octants. Not normalized: no traversal may depend on a
/// direction's length.
inline std::vector<Ray> rays_of_every_sign(const Vec3f& origin, std::size_t count, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> magnitude(0.05f, 1.0f);
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < count; ++i) {
        Vec3f d;
        for (int axis = 0; axis < 3; ++axis) {
            const std::size_t choice = (i >> (2 * axis)) % 4;  // positive, negative, +0, -0
            d[axis] = choice == 0 ? magnitude(rng) : choice == 1 ? -magnitude(rng) : choice == 2 ? 0.0f : -0.0f;
        }
        if (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f) d.x = -1.0f;
        rays.push_back({origin, d});
    }
    return rays;
}

/// Rays from random points inside the box in random directions; every other one with a random
/// [tmin, tmax] window scaled to the box's diagonal.
inline std::vector<Ray> windowed_rays_from_inside(const Aabb& box, std::size_t count, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), sym(-1.0f, 1.0f);
    const float diagonal = length(box.extent());
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < count; ++i) {
        Ray ray;
        ray.origin = box.lo + Vec3f{unit(rng), unit(rng), unit(rng)} * box.extent();
        ray.dir = normalize(Vec3f{sym(rng), sym(rng), sym(rng)});
        if (i % 2 == 0) {
            ray.tmin = unit(rng) * 0.3f * diagonal;
            ray.tmax = ray.tmin + unit(rng) * diagonal;
        }
        rays.push_back(ray);
    }
    return rays;
}

}  // namespace trident::testing
