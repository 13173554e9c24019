#pragma once
// The scene manifest of ../shared/BENCHMARK.md (scenes.json): a JSON array of entries naming an
// OBJ file (relative to the manifest) with its camera and light.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/scene.h"

namespace trident {

struct ManifestEntry {
    std::string name;
    std::filesystem::path file;          // resolved against the manifest's folder
    std::size_t expected_triangles = 0;  // 0 when the manifest does not say
    std::string kind;                    // "simple" / "complex" / ""
    CameraSpec camera;
    std::optional<PointLight> light;
    std::optional<std::array<std::uint32_t, 2>> resolution;
};

/// Throws SceneError naming the manifest (and the entry) when the file is missing, is not valid
/// JSON, or an entry lacks a name, a file or a camera.
std::vector<ManifestEntry> load_manifest(const std::filesystem::path& path);

}  // namespace trident
