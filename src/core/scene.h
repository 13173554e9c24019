#pragma once
// A scene: one mesh, the camera that views it, and an optional point light.
#include <optional>
#include <string>

#include "core/mesh.h"

namespace trident {

/// The look-at pinhole camera of ../shared/BENCHMARK.md.
struct CameraSpec {
    Vec3f eye{0.0f, 0.0f, 1.0f};
    Vec3f target{0.0f, 0.0f, 0.0f};
    Vec3f up{0.0f, 1.0f, 0.0f};
    float fov_y_deg = 60.0f;
};

struct PointLight {
    Vec3f position;
};

struct Scene {
    std::string name;
    Mesh mesh;
    CameraSpec camera;
    std::optional<PointLight> light;
};

}  // namespace trident
