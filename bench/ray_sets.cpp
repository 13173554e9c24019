#include "bench/ray_sets.h"

#include <fmt/format.h>

#include <algorithm>

#include "accel/any_accel.h"
#include "render/render_plan.h"
#include "render/trace.h"

namespace trident::bench {
namespace {

std::size_t traced(const SecondaryRays& rays) {
    return std::size_t(std::count_if(rays.rays.begin(), rays.rays.end(), [](const Ray& r) { return r.tmax > r.tmin; }));
}

bool asks(const std::vector<RayKind>& kinds, RayKind kind) {
    return std::find(kinds.begin(), kinds.end(), kind) != kinds.end();
}

}  // namespace

SceneRaySets make_scene_ray_sets(const Scene& scene, const Camera& camera, const std::vector<RayKind>& kinds) {
    SceneRaySets sets;
    RenderRequest request;
    request.benchmark = BenchmarkRays{asks(kinds, RayKind::shadow), asks(kinds, RayKind::diffuse)};
    const RenderPlan plan = make_render_plan(scene, request);
    if (!plan.shadow_pass && !plan.occlusion_pass) return sets;

    const AnyAccel bvh = AnyAccel::build(AccelKind::bvh, scene.mesh);
    const std::vector<Hit> hits = trace_primary(bvh, camera);
    constexpr std::size_t kOrderLanes = 16;  // 4x4 blocks: their 4x2 and 2x2 halves come first
    if (plan.shadow_pass) {
        sets.shadow = make_shadow_rays(scene.mesh, camera, hits, plan.light->position, kOrderLanes);
        sets.shadow_traced = traced(sets.shadow);
        sets.notes.push_back(fmt::format("{}: shadow rays toward the {} light at ({:.4g}, {:.4g}, {:.4g}); {} of {} hits "
                                         "face it and are traced",
                                         scene.name,
                                         plan.light_source == LightSource::scene
                                             ? "scene's"
                                             : "default (the scene has none: above the box by half its diagonal)",
                                         plan.light->position.x, plan.light->position.y, plan.light->position.z,
                                         sets.shadow_traced, sets.shadow.rays.size()));
    }
    if (plan.occlusion_pass) {
        sets.diffuse = make_diffuse_rays(scene.mesh, camera, hits, kOrderLanes);
        sets.diffuse_traced = traced(sets.diffuse);
        sets.notes.push_back(fmt::format("{}: {} diffuse rays (one cosine-distributed closest-hit ray per hit)", scene.name,
                                         sets.diffuse_traced));
    }
    return sets;
}

}  // namespace trident::bench
