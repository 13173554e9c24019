#include "scene/scene_source.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <numbers>

#include "scene/manifest.h"
#include "scene/obj_loader.h"
#include "scene/scene_error.h"
#include "scenes/builtin.h"

namespace trident {
namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

CameraSpec frame_bounds(const Aabb& bounds, float fov_y_deg) {
    CameraSpec camera;
    camera.fov_y_deg = fov_y_deg;
    camera.target = bounds.center();
    const float radius = std::max(0.5f * length(bounds.extent()), 1e-6f);
    const float distance = radius / std::sin(0.5f * fov_y_deg * std::numbers::pi_v<float> / 180.0f);
    const Vec3f view_dir = normalize(Vec3f{0.55f, 0.45f, 1.0f});
    camera.eye = camera.target + view_dir * distance;
    camera.up = {0.0f, 1.0f, 0.0f};
    return camera;
}

LoadedScene load_scene(const std::string& spec, const std::optional<std::filesystem::path>& manifest) {
    const auto start = std::chrono::steady_clock::now();
    LoadedScene out;
    if (manifest) {
        for (const ManifestEntry& entry : load_manifest(*manifest)) {
            if (entry.name != spec) continue;
            out.scene.name = entry.name;
            out.scene.mesh = load_obj(entry.file);
            out.scene.camera = entry.camera;
            out.scene.light = entry.light;
            out.source = fmt::format("{}: {}", manifest->string(), entry.name);
            out.load_ms = ms_since(start);
            return out;
        }
        if (!spec.ends_with(".obj"))
            throw SceneError(fmt::format("{}: no scene named '{}'", manifest->string(), spec));
    }
    if (is_builtin_scene(spec)) {
        out.scene = make_builtin_scene(spec);
        out.source = "built-in";
        out.load_ms = ms_since(start);
        return out;
    }
    if (spec.ends_with(".obj") || spec.ends_with(".OBJ") || std::filesystem::exists(spec)) {
        const std::filesystem::path path(spec);
        out.scene.name = path.stem().string();
        out.scene.mesh = load_obj(path);
        out.scene.camera = frame_bounds(out.scene.mesh.bounds());
        out.source = path.string();
        out.load_ms = ms_since(start);
        return out;
    }
    throw SceneError(fmt::format("'{}' is neither a built-in scene (see `trident scenes`) nor an .obj file", spec));
}

}  // namespace trident
