#include "render/shade.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/ray_offset.h"
#include "render/trace.h"

namespace trident {
namespace {

std::uint8_t to_byte(float linear) {
    const float encoded = std::pow(std::clamp(linear, 0.0f, 1.0f), 1.0f / 2.2f);
    return std::uint8_t(std::lround(encoded * 255.0f));
}

Rgb8 to_rgb(const Vec3f& linear) { return {to_byte(linear.x), to_byte(linear.y), to_byte(linear.z)}; }

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

const char* to_string(RenderMode mode) {
    switch (mode) {
        case RenderMode::shaded: return "shaded";
        case RenderMode::normal: return "normal";
        case RenderMode::depth: return "depth";
        case RenderMode::heat: return "heat";
    }
    return "?";
}

std::optional<RenderMode> parse_render_mode(std::string_view name) {
    for (RenderMode mode : {RenderMode::shaded, RenderMode::normal, RenderMode::depth, RenderMode::heat})
        if (name == to_string(mode)) return mode;
    return std::nullopt;
}

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

Image shade_shaded(const Scene& scene, const AnyAccel& accel, const Camera& camera, const std::vector<Hit>& hits,
                   SimdWidth width) {
    Image image(camera.width(), camera.height());
    const std::uint32_t w = camera.width();
    std::vector<Ray> shadow_rays;
    if (scene.light) {
        // One shadow ray per lit-facing hit, origin pushed off the surface along the geometric normal.
        shadow_rays.assign(hits.size(), Ray{{}, {1.0f, 0.0f, 0.0f}, 0.0f, 0.0f});
        for (std::size_t i = 0; i < hits.size(); ++i) {
            if (!hits[i].is_hit()) continue;
            const Ray primary = camera.primary_ray(std::uint32_t(i % w), std::uint32_t(i / w));
            const Vec3f p = primary.origin + primary.dir * hits[i].t;
            const Vec3f ng = face_forward(geometric_normal(scene.mesh, hits[i].triangle), primary.dir);
            const Vec3f to_light = scene.light->position - p;
            if (dot(to_light, ng) <= 0.0f) continue;  // the light is behind the surface: no ray needed
            const Vec3f origin = offset_ray_origin(p, ng);
            const Vec3f d = scene.light->position - origin;
            const float distance = length(d);
            shadow_rays[i] = Ray{origin, d / distance, 0.0f, distance * (1.0f - 1e-5f)};
        }
    }
    const std::vector<std::uint8_t> occluded =
        scene.light ? trace_occlusion(accel, shadow_rays, TriangleTest::watertight, width) : std::vector<std::uint8_t>{};
    for (std::size_t i = 0; i < hits.size(); ++i) {
        const auto x = std::uint32_t(i % w), y = std::uint32_t(i / w);
        if (!hits[i].is_hit()) {
            image.at(x, y) = background(camera, y);
            continue;
        }
        const Ray primary = camera.primary_ray(x, y);
        const Vec3f n = shading_normal(scene.mesh, hits[i], primary.dir);
        float light = 0.0f;
        if (scene.light) {
            const Vec3f p = primary.origin + primary.dir * hits[i].t;
            const bool lit = shadow_rays[i].tmax > shadow_rays[i].tmin && !occluded[i];
            light = 0.12f + (lit ? 0.88f * std::max(0.0f, dot(n, normalize(scene.light->position - p))) : 0.0f);
        } else {
            light = 0.15f + 0.85f * std::abs(dot(n, primary.dir));
        }
        image.at(x, y) = to_rgb(kAlbedo * light);
    }
    return image;
}

Image shade_normal(const Scene& scene, const Camera& camera, const std::vector<Hit>& hits) {
    Image image(camera.width(), camera.height());
    for (std::size_t i = 0; i < hits.size(); ++i) {
        const auto x = std::uint32_t(i % camera.width()), y = std::uint32_t(i / camera.width());
        if (!hits[i].is_hit()) continue;
        const Vec3f n = shading_normal(scene.mesh, hits[i], camera.primary_ray(x, y).dir);
        const Vec3f c = n * 0.5f + Vec3f{0.5f};
        image.at(x, y) = {std::uint8_t(c.x * 255.0f), std::uint8_t(c.y * 255.0f), std::uint8_t(c.z * 255.0f)};
    }
    return image;
}

Image shade_depth(const Camera& camera, const std::vector<Hit>& hits) {
    Image image(camera.width(), camera.height());
    float nearest = kInfinity, farthest = 0.0f;
    for (const Hit& h : hits)
        if (h.is_hit()) { nearest = std::min(nearest, h.t); farthest = std::max(farthest, h.t); }
    const float range = farthest > nearest ? farthest - nearest : 1.0f;
    for (std::size_t i = 0; i < hits.size(); ++i) {
        if (!hits[i].is_hit()) continue;
        const auto level = std::uint8_t(std::lround(255.0f * (1.0f - 0.85f * (hits[i].t - nearest) / range)));
        image.pixels[i] = {level, level, level};
    }
    return image;
}

Image shade_heat(const Camera& camera, const std::vector<TraversalCounters>& counts) {
    // A perceptually ordered ramp (dark blue -> teal -> yellow -> white-hot), sampled linearly.
    static constexpr std::array<Vec3f, 5> kRamp{Vec3f{0.02f, 0.02f, 0.10f}, Vec3f{0.10f, 0.25f, 0.60f},
                                               Vec3f{0.10f, 0.65f, 0.55f}, Vec3f{0.95f, 0.85f, 0.20f},
                                               Vec3f{1.0f, 1.0f, 1.0f}};
    Image image(camera.width(), camera.height());
    std::uint64_t most = 1;
    for (const TraversalCounters& c : counts) most = std::max(most, c.nodes_visited);
    for (std::size_t i = 0; i < counts.size(); ++i) {
        const float s = float(counts[i].nodes_visited) / float(most) * float(kRamp.size() - 1);
        const auto k = std::min(std::size_t(s), kRamp.size() - 2);
        const float f = s - float(k);
        const Vec3f c = kRamp[k] * (1.0f - f) + kRamp[k + 1] * f;
        image.pixels[i] = {std::uint8_t(c.x * 255.0f), std::uint8_t(c.y * 255.0f), std::uint8_t(c.z * 255.0f)};
    }
    return image;
}

}  // namespace trident
