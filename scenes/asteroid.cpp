#include "scenes/asteroid.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "scenes/gradient_noise.h"
#include "scenes/hash_random.h"
#include "scenes/mesh_builder.h"

namespace trident {

namespace {

struct Crater {
    Vec3f center;  // unit direction
    float radius;  // chord length on the unit sphere
    float depth;   // relative to the local radius
};

std::vector<Crater> scatter_craters(std::uint64_t seed, int count) {
    HashRandom rng(seed);
    std::vector<Crater> craters;
    for (int k = 0; k < count; ++k) {
        const float z = rng.uniform(-1.0f, 1.0f), phi = rng.uniform(0.0f, 2.0f * std::numbers::pi_v<float>);
        const float ring = std::sqrt(1.0f - z * z);
        const float size = rng.uniform();
        const float radius = 0.05f + 0.35f * size * size * size;  // many small, few large
        craters.push_back({{ring * std::cos(phi), ring * std::sin(phi), z}, radius, 0.3f * radius});
    }
    return craters;
}

/// Relative height of the crater field at direction d: a flat-floored bowl inside each crater and
/// a raised rim around it.
float crater_height(const Vec3f& d, const std::vector<Crater>& craters) {
    float h = 0.0f;
    for (const Crater& c : craters) {
        const float x = length(d - c.center) / c.radius;
        if (x >= 2.5f) continue;
        const float bowl = x < 1.0f ? std::max(x * x - 1.0f, -0.7f) : 0.0f;
        const float rim_offset = (x - 1.0f) / 0.3f;
        h += c.depth * (bowl + 0.35f * std::exp(-rim_offset * rim_offset));
    }
    return h;
}

/// Radius of the ellipsoid with semi-axes `axes` along unit direction d.
float ellipsoid_radius(const Vec3f& d, const Vec3f& axes) {
    const Vec3f q{d.x / axes.x, d.y / axes.y, d.z / axes.z};
    return 1.0f / length(q);
}

}  // namespace

std::size_t asteroid_triangle_count(std::uint32_t frequency) { return GeodesicSphere{frequency}.triangle_count(); }

Mesh make_asteroid(std::uint32_t frequency, std::uint64_t seed) {
    MeshBuilder builder;
    builder.add(GeodesicSphere{frequency});
    Mesh mesh = builder.build();
    const std::vector<Crater> craters = scatter_craters(hash_combine(seed, 1), 90);
    const std::uint64_t lump_seed = hash_combine(seed, 2), detail_seed = hash_combine(seed, 3);
    const Vec3f axes{1.3f, 0.85f, 1.0f};
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, mesh.vertex_count(), 1024), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                const Vec3f d = mesh.vertex(std::uint32_t(i));
                const float relief = 0.25f * fractal_noise(d * 1.3f, 3, lump_seed) +
                                     0.04f * fractal_noise(d * 5.0f, 4, detail_seed) + crater_height(d, craters);
                const Vec3f p = d * (ellipsoid_radius(d, axes) * std::max(1.0f + relief, 0.4f));
                mesh.x[i] = p.x;
                mesh.y[i] = p.y;
                mesh.z[i] = p.z;
            }
        });
    return mesh;
}

}  // namespace trident
