#pragma once
// Turning primary hits into an image. `shaded` is Lambert under the scene's point light with shadow
// rays (a headlight without shadow rays when the scene has no light); `normal` shows the shading
// normal; `depth` the hit distance; `heat` the traversal cost per pixel.
#include <optional>
#include <string_view>
#include <vector>

#include "accel/any_accel.h"
#include "camera/camera.h"
#include "core/scene.h"
#include "render/image.h"
#include "simd/width.h"

namespace trident {

enum class RenderMode { shaded, normal, depth, heat };

const char* to_string(RenderMode mode);
std::optional<RenderMode> parse_render_mode(std::string_view name);

/// The normal used for shading at a hit: interpolated vertex normals where the mesh has them, the
/// geometric normal otherwise; normalized and turned to face the incoming ray.
Vec3f shading_normal(const Mesh& mesh, const Hit& hit, const Vec3f& ray_dir);

/// Images for the modes that need only hits (shaded traces its own shadow rays through `accel`).
Image shade_shaded(const Scene& scene, const AnyAccel& accel, const Camera& camera, const std::vector<Hit>& hits,
                   SimdWidth width = SimdWidth::scalar);
Image shade_normal(const Scene& scene, const Camera& camera, const std::vector<Hit>& hits);
Image shade_depth(const Camera& camera, const std::vector<Hit>& hits);
/// Nodes visited per pixel on a perceptual colour ramp, scaled to the image's maximum.
Image shade_heat(const Camera& camera, const std::vector<TraversalCounters>& counts);

}  // namespace trident
