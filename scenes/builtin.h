#pragma once
// The built-in procedural scenes: generated in code, deterministically, so the benchmark and the
// tests run with no files. Each comes with a camera framing it for a 16:9 image and a point light.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "core/scene.h"

namespace trident {

struct BuiltinSceneInfo {
    std::string name;
    std::string description;  // one line
    std::size_t triangles;    // exact, computed without generating the mesh
    bool closed;              // every edge shared by exactly two consistently wound triangles
};

std::vector<BuiltinSceneInfo> builtin_scenes();
std::vector<std::string> builtin_scene_names();
bool is_builtin_scene(std::string_view name);
/// Generates the named scene; throws std::invalid_argument naming it if there is no such scene.
Scene make_builtin_scene(std::string_view name);

}  // namespace trident
