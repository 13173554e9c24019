#include "bench/scene_selection.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <stdexcept>

#include "scene/manifest.h"
#include "scenes/builtin.h"

namespace trident::bench {
namespace {

/// The names kept by --only, in the order `available` lists them; every --only name must exist.
std::vector<std::string> narrow(const std::vector<std::string>& available, const std::vector<std::string>& only,
                                const std::string& where) {
    for (const std::string& name : only)
        if (std::find(available.begin(), available.end(), name) == available.end())
            throw std::invalid_argument(
                fmt::format("--only {}: no such scene in {} ({})", name, where, fmt::join(available, ", ")));
    if (only.empty()) return available;
    std::vector<std::string> kept;
    for (const std::string& name : available)
        if (std::find(only.begin(), only.end(), name) != only.end()) kept.push_back(name);
    return kept;
}

}  // namespace

std::vector<SceneChoice> select_scenes(const BenchOptions& options) {
    std::vector<SceneChoice> scenes;
    if (options.manifest) {
        std::vector<std::string> names;
        for (const ManifestEntry& entry : load_manifest(*options.manifest)) names.push_back(entry.name);
        for (std::string& name : narrow(names, options.only, options.manifest->string()))
            scenes.push_back({std::move(name), options.manifest});
    }
    for (const std::string& spec : options.scene_specs) scenes.push_back({spec, std::nullopt});
    if (options.manifest || !options.scene_specs.empty()) {
        if (!options.only.empty() && !options.manifest)
            throw std::invalid_argument("--only picks from --scenes or from the built-in scenes, not from --scene");
        return scenes;
    }
    std::vector<std::string> builtin_names;
    for (const BuiltinSceneInfo& info : builtin_scenes()) builtin_names.push_back(info.name);
    for (std::string& name : narrow(builtin_names, options.only, "the built-in scenes"))
        scenes.push_back({std::move(name), std::nullopt});
    return scenes;
}

}  // namespace trident::bench
