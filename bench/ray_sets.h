#pragma once
// The ray kinds trident-bench times (`--rays primary,shadow,diffuse`) and the secondary rays of a
// scene, made once so every structure, traversal and Embree trace exactly the same rays.
// Shadow rays go from every primary hit to the scene's light, or, when the scene has none, to the
// default light of render/render_plan.h (above the scene box); diffuse rays are one
// cosine-distributed closest-hit ray per primary hit about the geometric normal.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "camera/camera.h"
#include "core/scene.h"
#include "render/secondary_rays.h"

namespace trident::bench {

enum class RayKind { primary, shadow, diffuse };

inline constexpr RayKind kAllRayKinds[] = {RayKind::primary, RayKind::shadow, RayKind::diffuse};

constexpr const char* to_string(RayKind kind) {
    switch (kind) {
        case RayKind::primary: return "primary";
        case RayKind::shadow: return "shadow";
        case RayKind::diffuse: return "diffuse";
    }
    return "?";
}

inline std::optional<RayKind> parse_ray_kind(std::string_view name) {
    for (RayKind kind : kAllRayKinds)
        if (name == to_string(kind)) return kind;
    return std::nullopt;
}

/// A scene's secondary rays in packet order (4x4 primary blocks), and what the report says of them.
struct SceneRaySets {
    SecondaryRays shadow, diffuse;
    std::size_t shadow_traced = 0, diffuse_traced = 0;  // rays with tmax > tmin: the Mrays/s count
    std::vector<std::string> notes;                     // the plan's lines for these rays
};

/// Traces the primary rays once (our BVH, single rays) and makes the rays `kinds` asks for.
SceneRaySets make_scene_ray_sets(const Scene& scene, const Camera& camera, const std::vector<RayKind>& kinds);

}  // namespace trident::bench
