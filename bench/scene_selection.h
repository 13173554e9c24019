#pragma once
// Which scenes a run measures: the manifest's (--scenes, narrowed by --only), any --scene given
// by name or path, and otherwise every built-in scene (narrowed by --only), so a plain
// `trident-bench` needs no files.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bench/options.h"

namespace trident::bench {

struct SceneChoice {
    std::string spec;                               // what load_scene() is given
    std::optional<std::filesystem::path> manifest;  // set for manifest entries
};

/// Throws SceneError when the manifest cannot be read, std::invalid_argument when --only names
/// a scene that is not there.
std::vector<SceneChoice> select_scenes(const BenchOptions& options);

}  // namespace trident::bench
