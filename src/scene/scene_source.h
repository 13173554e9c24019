#pragma once
// Turns what a user names into a Scene: a built-in scene's name, a path to an .obj file, or the
// name of an entry in a manifest.
#include <filesystem>
#include <optional>
#include <string>

#include "core/scene.h"

namespace trident {

struct LoadedScene {
    Scene scene;
    double load_ms = 0.0;        // parsing (or generating) the mesh
    std::string source;          // "built-in", the OBJ path, or "MANIFEST: name"
};

/// Throws SceneError with one line naming what could not be loaded.
LoadedScene load_scene(const std::string& spec, const std::optional<std::filesystem::path>& manifest = {});

/// A camera that frames a bounding box: looking at its centre from above and in front, far enough
/// that the bounding sphere fits the vertical field of view.
CameraSpec frame_bounds(const Aabb& bounds, float fov_y_deg = 45.0f);

}  // namespace trident
