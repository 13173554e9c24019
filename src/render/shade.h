#pragma once
// Turning primary hits into an image, doing only what the render plan asks (render_plan.h).
// `shaded` is Lambert under the scene's point light with shadow rays (a headlight without shadow
// rays when the scene has no light); `normal` shows the shading normal; `depth` the hit distance;
// `ao` ambient occlusion; heat maps are in heat_map.h.
#include <vector>

#include "accel/any_accel.h"
#include "camera/camera.h"
#include "core/scene.h"
#include "render/image.h"
#include "render/render_plan.h"
#include "simd/width.h"

namespace trident {

/// The normal used for shading at a hit: interpolated vertex normals where the mesh has them, the
/// geometric normal otherwise; normalized and turned to face the incoming ray.
Vec3f shading_normal(const Mesh& mesh, const Hit& hit, const Vec3f& ray_dir);
/// The same with the source the plan chose (NormalSource::none is treated as geometric).
Vec3f shading_normal(const Mesh& mesh, const Hit& hit, const Vec3f& ray_dir, NormalSource source);

/// Whether each pixel's hit sees the plan's light: 1 lit, 0 in shadow or facing away, and 0 for
/// misses. Shadow rays are traced per tile as the plan's shadow traversal says.
std::vector<std::uint8_t> light_visibility(const Scene& scene, const AnyAccel& accel, const Camera& camera,
                                           const std::vector<Hit>& hits, const RenderPlan& plan);
/// Per pixel, the share of the plan's AO rays that escape (1: fully open; misses get 1).
std::vector<float> ambient_visibility(const Scene& scene, const AnyAccel& accel, const Camera& camera,
                                      const std::vector<Hit>& hits, const RenderPlan& plan);

Image shade_shaded(const Scene& scene, const AnyAccel& accel, const Camera& camera, const std::vector<Hit>& hits,
                   const RenderPlan& plan);
Image shade_normal(const Scene& scene, const Camera& camera, const std::vector<Hit>& hits, const RenderPlan& plan);
Image shade_depth(const Camera& camera, const std::vector<Hit>& hits);
Image shade_ao(const Scene& scene, const AnyAccel& accel, const Camera& camera, const std::vector<Hit>& hits,
               const RenderPlan& plan);

}  // namespace trident
