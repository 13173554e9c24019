#include "render/shade.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/ray_offset.h"
#include "render/gamma.h"
#include "render/image_tiles.h"
#include "render/ray_stream.h"
#include "render/secondary_rays.h"

namespace trident {
namespace {

Rgb8 to_rgb(const Vec3f& linear) { return {gamma_byte(linear.x), gamma_byte(linear.y), gamma_byte(linear.z)}; }

/// per_pixel(x, y, i) for every pixel (i = y * width + x), tile by tile on the renderer's threads
/// (image_tiles.h): a pixel's shading reads its own hit and writes its own pixel. Serial, this
/// loop took most of a shaded render's shading time on Teapot.
template <class PerPixel>
void for_each_pixel(const Camera& camera, PerPixel&& per_pixel) {
    for_each_image_tile(camera, [&](const ImageTile& tile) {
        for (std::uint32_t y = tile.y0; y != tile.y1; ++y)
            for (std::uint32_t x = tile.x0; x != tile.x1; ++x) per_pixel(x, y, std::size_t(y) * camera.width() + x);
    });
}

Rgb8 background(const Camera& camera, std::uint32_t y) {
    const float s = float(y) / float(std::max(camera.height(), 1u));
    return to_rgb(Vec3f{0.05f, 0.07f, 0.12f} * (1.0f - 0.5f * s));
}

Vec3f geometric_normal(const Mesh& mesh, TriangleId triangle) {
    const Vec3f n = triangle_of(mesh, triangle).geometric_normal();
    const float len = length(n);
    return len > 0.0f ? n / len : Vec3f{0.0f, 1.0f, 0.0f};
}

Vec3f face_forward(const Vec3f& n, const Vec3f& dir) { return dot(n, dir) > 0.0f ? -n : n; }

constexpr Vec3f kAlbedo{0.75f, 0.72f, 0.66f};

}  // namespace

Vec3f shading_normal(const Mesh& mesh, const Hit& hit, const Vec3f& ray_dir) {
    const Vec3f geometric = face_forward(geometric_normal(mesh, hit.triangle), ray_dir);
    if (!mesh.has_normals()) return geometric;
    const IndexTriple& t = mesh.normal_triangles[hit.triangle];
    const Vec3f n = mesh.normal(t.v0) * (1.0f - hit.u - hit.v) + mesh.normal(t.v1) * hit.u + mesh.normal(t.v2) * hit.v;
    const float len = length(n);
    if (!(len > 0.0f)) return geometric;
    // Interpolated normals can point away from the viewer near silhouettes; keep them on its side.
    return face_forward(n / len, ray_dir);
}

Vec3f shading_normal(const Mesh& mesh, const Hit& hit, const Vec3f& ray_dir, NormalSource source) {
    if (source == NormalSource::interpolated) return shading_normal(mesh, hit, ray_dir);
    return face_forward(geometric_normal(mesh, hit.triangle), ray_dir);
}

std::vector<std::uint8_t> light_visibility(const Scene& scene, const AnyAccel& accel, const Camera& camera,
                                           const std::vector<Hit>& hits, const RenderPlan& plan) {
    std::vector<std::uint8_t> lit(hits.size(), 0);
    if (!plan.shadow_pass || !plan.light) return lit;
    const Vec3f light = plan.light->position;
    const std::size_t lanes = lane_count(plan.shadow_traversal.width);
    for_each_image_tile(camera, [&](const ImageTile& tile) {
        // The tile's shadow rays in the order of its primary packets: lanes of a shadow packet
        // start from the pixels of one primary packet.
        std::vector<Ray> rays;
        std::vector<std::uint32_t> pixels;
        for (std::uint32_t pixel : pixels_in_packet_order(camera, tile, lanes)) {
            if (!hits[pixel].is_hit()) continue;
            const Ray primary = camera.primary_ray(pixel % camera.width(), pixel / camera.width());
            rays.push_back(shadow_ray(scene.mesh, primary, hits[pixel], light));
            pixels.push_back(pixel);
        }
        std::vector<std::uint8_t> occluded(rays.size());
        occlude_stream(accel, rays, occluded, plan.shadow_traversal);
        for (std::size_t i = 0; i < rays.size(); ++i)
            lit[pixels[i]] = rays[i].tmax > rays[i].tmin && !occluded[i];
    });
    return lit;
}

std::vector<float> ambient_visibility(const Scene& scene, const AnyAccel& accel, const Camera& camera,
                                      const std::vector<Hit>& hits, const RenderPlan& plan) {
    std::vector<float> open(hits.size(), 1.0f);
    if (!plan.occlusion_pass || plan.occlusion_samples == 0) return open;
    const std::uint32_t samples = plan.occlusion_samples;
    const std::size_t lanes = lane_count(plan.occlusion_traversal.width);
    for_each_image_tile(camera, [&](const ImageTile& tile) {
        std::vector<Ray> rays;
        std::vector<std::uint32_t> pixels;
        for (std::uint32_t pixel : pixels_in_packet_order(camera, tile, lanes)) {
            if (!hits[pixel].is_hit()) continue;
            const Ray primary = camera.primary_ray(pixel % camera.width(), pixel / camera.width());
            const Vec3f p = surface_point(scene.mesh, hits[pixel]);
            const Vec3f ng = facing_geometric_normal(scene.mesh, hits[pixel].triangle, primary.dir);
            const Vec3f n = shading_normal(scene.mesh, hits[pixel], primary.dir, plan.normals);
            for (std::uint32_t s = 0; s < samples; ++s)
                rays.push_back(hemisphere_ray(p, ng, n, sample_uniforms(pixel, s), plan.occlusion_radius));
            pixels.push_back(pixel);
        }
        std::vector<std::uint8_t> occluded(rays.size());
        occlude_stream(accel, rays, occluded, plan.occlusion_traversal);
        // A pixel's samples are consecutive: rays[k * samples .. (k + 1) * samples) for pixels[k].
        for (std::size_t k = 0; k < pixels.size(); ++k) {
            std::uint32_t escaped = 0;
            for (std::size_t i = k * samples; i < (k + 1) * samples; ++i)
                escaped += rays[i].tmax > rays[i].tmin && !occluded[i];
            open[pixels[k]] = float(escaped) / float(samples);
        }
    });
    return open;
}

Image shade_shaded(const Scene& scene, const AnyAccel& accel, const Camera& camera, const std::vector<Hit>& hits,
                   const RenderPlan& plan) {
    Image image(camera.width(), camera.height());
    const std::vector<std::uint8_t> lit = light_visibility(scene, accel, camera, hits, plan);
    for_each_pixel(camera, [&](std::uint32_t x, std::uint32_t y, std::size_t i) {
        if (!hits[i].is_hit()) {
            image.at(x, y) = background(camera, y);
            return;
        }
        const Ray primary = camera.primary_ray(x, y);
        const Vec3f n = shading_normal(scene.mesh, hits[i], primary.dir, plan.normals);
        float light = 0.0f;
        if (plan.shadow_pass) {
            light = 0.12f;
            if (lit[i]) {  // the hit point only where the light reaches it
                const Vec3f p = surface_point(scene.mesh, hits[i]);
                light += 0.88f * std::max(0.0f, dot(n, normalize(plan.light->position - p)));
            }
        } else {
            light = 0.15f + 0.85f * std::abs(dot(n, primary.dir));
        }
        image.at(x, y) = to_rgb(kAlbedo * light);
    });
    return image;
}

Image shade_ao(const Scene& scene, const AnyAccel& accel, const Camera& camera, const std::vector<Hit>& hits,
               const RenderPlan& plan) {
    Image image(camera.width(), camera.height());
    const std::vector<float> open = ambient_visibility(scene, accel, camera, hits, plan);
    for_each_pixel(camera, [&](std::uint32_t x, std::uint32_t y, std::size_t i) {
        image.at(x, y) = hits[i].is_hit() ? to_rgb(Vec3f{open[i]}) : background(camera, y);
    });
    return image;
}

Image shade_normal(const Scene& scene, const Camera& camera, const std::vector<Hit>& hits, const RenderPlan& plan) {
    Image image(camera.width(), camera.height());
    for_each_pixel(camera, [&](std::uint32_t x, std::uint32_t y, std::size_t i) {
        if (!hits[i].is_hit()) return;
        const Vec3f n = shading_normal(scene.mesh, hits[i], camera.primary_ray(x, y).dir, plan.normals);
        const Vec3f c = n * 0.5f + Vec3f{0.5f};
        image.at(x, y) = {std::uint8_t(c.x * 255.0f), std::uint8_t(c.y * 255.0f), std::uint8_t(c.z * 255.0f)};
    });
    return image;
}

Image shade_depth(const Camera& camera, const std::vector<Hit>& hits) {
    Image image(camera.width(), camera.height());
    float nearest = kInfinity, farthest = 0.0f;
    for (const Hit& h : hits)
        if (h.is_hit()) { nearest = std::min(nearest, h.t); farthest = std::max(farthest, h.t); }
    const float range = farthest > nearest ? farthest - nearest : 1.0f;
    for_each_pixel(camera, [&](std::uint32_t, std::uint32_t, std::size_t i) {
        if (!hits[i].is_hit()) return;
        const auto level = std::uint8_t(std::lround(255.0f * (1.0f - 0.85f * (hits[i].t - nearest) / range)));
        image.pixels[i] = {level, level, level};
    });
    return image;
}

}  // namespace trident
