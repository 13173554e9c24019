#include "render/secondary_rays.h"

#include "core/ray_offset.h"
#include "render/trace.h"

namespace trident {

std::vector<std::uint32_t> pixels_in_packet_order(const Camera& camera, const ImageTile& tile, std::size_t lanes) {
    const auto [bw, bh] = lanes <= 1 ? std::pair{kRenderTileSize, 1u} : packet_block(lanes);
    std::vector<std::uint32_t> pixels;
    pixels.reserve(std::size_t(tile.x1 - tile.x0) * (tile.y1 - tile.y0));
    for (std::uint32_t by = tile.y0; by < tile.y1; by += bh)
        for (std::uint32_t bx = tile.x0; bx < tile.x1; bx += bw)
            for (std::uint32_t y = by; y < std::min(by + bh, tile.y1); ++y)
                for (std::uint32_t x = bx; x < std::min(bx + bw, tile.x1); ++x)
                    pixels.push_back(y * camera.width() + x);
    return pixels;
}

Vec3f facing_geometric_normal(const Mesh& mesh, TriangleId triangle, const Vec3f& incoming) {
    const Vec3f n = triangle_of(mesh, triangle).geometric_normal();
    const float len = length(n);
    const Vec3f unit = len > 0.0f ? n / len : Vec3f{0.0f, 1.0f, 0.0f};
    return dot(unit, incoming) > 0.0f ? -unit : unit;
}

Vec3f surface_point(const Mesh& mesh, const Hit& hit) {
    const Triangle tri = triangle_of(mesh, hit.triangle);
    return tri.a + (tri.b - tri.a) * hit.u + (tri.c - tri.a) * hit.v;
}

Ray shadow_ray(const Mesh& mesh, const Ray& primary, const Hit& hit, const Vec3f& light) {
    constexpr Ray kNothing{{}, {1.0f, 0.0f, 0.0f}, 0.0f, 0.0f};
    const Vec3f p = surface_point(mesh, hit);
    const Vec3f ng = facing_geometric_normal(mesh, hit.triangle, primary.dir);
    if (!(dot(light - p, ng) > 0.0f)) return kNothing;  // the light is behind the surface: in shadow
    const Vec3f origin = offset_ray_origin(p, ng);
    const Vec3f d = light - origin;
    const float distance = length(d);
    if (!(distance > 0.0f)) return kNothing;
    // Stop a hair before the light so a light lying on a surface is not shadowed by it.
    return Ray{origin, d / distance, 0.0f, distance * (1.0f - 1e-5f)};
}

Ray hemisphere_ray(const Vec3f& point, const Vec3f& ng, const Vec3f& about, UniformPair u, float tmax) {
    const Vec3f d = cosine_direction(about, u);
    if (!(dot(d, ng) > 0.0f)) return Ray{point, d, 0.0f, 0.0f};
    return Ray{offset_ray_origin(point, ng), d, 0.0f, tmax};
}

namespace {

template <class MakeRay>
SecondaryRays make_per_hit(const Camera& camera, std::span<const Hit> hits, std::size_t lanes, MakeRay&& make_ray) {
    SecondaryRays out;
    for (std::size_t t = 0; t < tile_count(camera); ++t)
        for (std::uint32_t pixel : pixels_in_packet_order(camera, tile_at(camera, t), lanes)) {
            if (!hits[pixel].is_hit()) continue;
            const Ray primary = camera.primary_ray(pixel % camera.width(), pixel / camera.width());
            out.rays.push_back(make_ray(primary, hits[pixel], pixel));
            out.pixel.push_back(pixel);
        }
    return out;
}

}  // namespace

SecondaryRays make_shadow_rays(const Mesh& mesh, const Camera& camera, std::span<const Hit> hits, const Vec3f& light,
                               std::size_t lanes) {
    return make_per_hit(camera, hits, lanes,
                        [&](const Ray& primary, const Hit& hit, std::uint32_t) { return shadow_ray(mesh, primary, hit, light); });
}

SecondaryRays make_diffuse_rays(const Mesh& mesh, const Camera& camera, std::span<const Hit> hits, std::size_t lanes,
                                std::uint64_t seed) {
    return make_per_hit(camera, hits, lanes, [&](const Ray& primary, const Hit& hit, std::uint32_t pixel) {
        const Vec3f ng = facing_geometric_normal(mesh, hit.triangle, primary.dir);
        return hemisphere_ray(surface_point(mesh, hit), ng, ng, sample_uniforms(pixel, 0, seed), kInfinity);
    });
}

}  // namespace trident
