#pragma once
// How much work a test case does in the AddressSanitizer + UndefinedBehaviorSanitizer build.
//
// That build runs every test case the Release build runs, to catch memory errors and undefined
// behaviour; it does not need the Release run's volume to do so. At -Og with both sanitizers the
// traversals and builders run 10 to 30 times slower than in the Release build, so the heaviest
// cases trace fewer rays there, and the scene loops stop at the asteroid's 144,500 triangles:
// the city's million took most of a minute per structure to build, and the hall's 294,000 about
// 20 s of the run's 288 s of tests (the builders meet large triangles and spatial splits in cases
// of their own). The Release run keeps the full workloads, the hall and the city included.
// bench/experiments/test_time.md has the figures.
#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "scenes/builtin.h"

namespace trident::testing {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif

/// The largest built-in scene (in triangles) the scene loops build under the sanitizers.
inline constexpr std::size_t kSanitizedSceneTriangles = 200'000;

/// `count` in the Release build, `count / divisor` (at least 1) under the sanitizers.
constexpr std::size_t workload(std::size_t count, std::size_t divisor) {
    return kSanitized ? std::max<std::size_t>(1, count / divisor) : count;
}

/// The built-in scenes a loop over "every built-in scene" walks in this build.
inline std::vector<BuiltinSceneInfo> builtin_scenes_under_test() {
    std::vector<BuiltinSceneInfo> scenes = builtin_scenes();
    if (kSanitized)
        std::erase_if(scenes, [](const BuiltinSceneInfo& info) { return info.triangles > kSanitizedSceneTriangles; });
    return scenes;
}

inline std::vector<std::string> builtin_scene_names_under_test() {
    std::vector<std::string> names;
    for (const BuiltinSceneInfo& info : builtin_scenes_under_test()) names.push_back(info.name);
    return names;
}

}  // namespace trident::testing
