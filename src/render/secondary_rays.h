#pragma once
// Secondary rays made from primary hits: shadow rays toward a point light and cosine-distributed
// rays about a normal, with origins pushed off the surface (core/ray_offset.h). Rays come in the
// order of the primary packets that made the hits (tile by tile, packet block by packet block),
// so a run of `lanes` consecutive rays starts from neighbouring pixels.
#include <cstdint>
#include <span>
#include <vector>

#include "camera/camera.h"
#include "core/mesh.h"
#include "core/ray.h"
#include "render/hemisphere_sample.h"
#include "render/image_tiles.h"

namespace trident {

/// The tile's pixel indices in the order packets of `lanes` rays take them (row order for 1).
std::vector<std::uint32_t> pixels_in_packet_order(const Camera& camera, const ImageTile& tile, std::size_t lanes);

/// The unit geometric normal of a triangle turned to face the incoming direction.
Vec3f facing_geometric_normal(const Mesh& mesh, TriangleId triangle, const Vec3f& incoming);

/// Where `hit` lies on its triangle, from the corners and the barycentrics: a + u (b - a) + v (c - a).
/// Its rounding error is a few ulps of the corners' coordinates, which is what offset_ray_origin
/// (core/ray_offset.h) moves the point by. origin + t * dir is off by a few ulps of t * |dir|
/// instead: on a floor near y = 0 seen from 2,000 units away, many times that offset, and the
/// secondary ray starts below the floor (tests/render/test_shadow_rays.cpp).
Vec3f surface_point(const Mesh& mesh, const Hit& hit);

/// From the hit of `primary` to the light; tmax = tmin = 0 (nothing to trace, in shadow) when the
/// light is behind the surface as the ray saw it. The ray stops just short of the light.
Ray shadow_ray(const Mesh& mesh, const Ray& primary, const Hit& hit, const Vec3f& light);

/// A cosine-distributed ray about `about` (unit, on the incoming side) from the hit point, origin
/// offset along the facing geometric normal `ng`; tmax = tmin = 0 when the direction dives below
/// the geometric surface (an interpolated normal can lean past it): that ray counts as blocked.
Ray hemisphere_ray(const Vec3f& point, const Vec3f& ng, const Vec3f& about, UniformPair u, float tmax);

/// Rays for a whole image in packet order, with the pixel each came from.
struct SecondaryRays {
    std::vector<Ray> rays;
    std::vector<std::uint32_t> pixel;
};

/// One shadow ray per primary hit (misses make none).
SecondaryRays make_shadow_rays(const Mesh& mesh, const Camera& camera, std::span<const Hit> hits, const Vec3f& light,
                               std::size_t lanes);
/// One closest-hit diffuse ray (tmax infinite) per primary hit about the facing geometric normal,
/// sample 0 of each pixel under `seed`.
SecondaryRays make_diffuse_rays(const Mesh& mesh, const Camera& camera, std::span<const Hit> hits, std::size_t lanes,
                                std::uint64_t seed = 0);

}  // namespace trident
