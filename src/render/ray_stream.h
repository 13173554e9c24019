#pragma once
// Tracing a list of secondary rays (shadow, ambient-occlusion, diffuse-bounce) on the calling
// thread, one at a time or as packets, cut from the list in order or by direction octant
// (stream_packets.h). Rays with tmax <= tmin are not traced: unoccluded, no hit. And tracing rays
// that stay in the caller's arrays (the Python module's), a tile of an image of them at a time.
#include <cstddef>
#include <cstdint>
#include <span>

#include "accel/any_accel.h"
#include "core/intersect_triangle.h"
#include "core/ray_coherence.h"
#include "core/slab_test.h"
#include "render/image_tiles.h"
#include "render/ray_arrays.h"
#include "render/stream_packets.h"
#include "simd/width.h"

namespace trident {

/// How a stream is traced: single rays (width scalar) or packets of `width` lanes grouped so, with
/// the robust or the fast slab test; `coherence` is the caller's hint, as Embree's context flags:
/// single closest-hit rays take it (the wide BVH prefetches for incoherent ones), and packets of an
/// incoherent stream that would all walk their lanes alone are never cut (stream_walks_rays_alone).
struct StreamTraversal {
    SimdWidth width = SimdWidth::scalar;
    PacketGrouping grouping = PacketGrouping::in_order;
    SlabTest slabs = SlabTest::robust;
    RayCoherence coherence = RayCoherence::coherent;
    /// Any hit: each ray, or packet, of a list first tests the occluder that stopped the one
    /// before, where the structure can (LastOccluder, accel/packet_kernels.h). Off, the rays are
    /// answered by the walk alone (to measure the structure by itself); the answers are the same.
    bool last_occluder = true;
};

/// Whether a packet traversal of the stream goes ray by ray from the start: the caller calls its
/// rays incoherent, and every incoherent packet of the structure walks its lanes alone from the
/// root (the wide BVH over a large tree, accel/bvh/wide_packet.h). Cutting such a stream into
/// octant packets and asking each whether its directions spread only to trace its rays alone cost
/// 3-6% of the single rays' time (bench/experiments/bvh-traversal.md, sixteenth session), as
/// Embree's incoherent packets go straight to its single-ray walk. The hits are the same.
bool stream_walks_rays_alone(const AnyAccel& accel, const StreamTraversal& traversal);

/// Any-hit: occluded[i] = 1 when rays[i] hits anything in [tmin, tmax]. Throws std::runtime_error
/// when the structure has no packet traversal of that width.
void occlude_stream(const AnyAccel& accel, std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                    StreamTraversal traversal, TriangleTest test = TriangleTest::watertight);
/// Closest hit of each ray.
void intersect_stream(const AnyAccel& accel, std::span<const Ray> rays, std::span<Hit> hits, StreamTraversal traversal,
                      TriangleTest test = TriangleTest::watertight);

/// The same over all cores, the list cut into chunks of consecutive rays.
void occlude_stream_parallel(const AnyAccel& accel, std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                             StreamTraversal traversal, TriangleTest test = TriangleTest::watertight);
void intersect_stream_parallel(const AnyAccel& accel, std::span<const Ray> rays, std::span<Hit> hits,
                               StreamTraversal traversal, TriangleTest test = TriangleTest::watertight);

/// The tile's rays of an image of rays in arrays (render/ray_arrays.h), traced as the renderer
/// traces a tile of primary rays: packets of the traversal's width over the image's packet blocks,
/// or single rays. Results go to out[image.index(x, y)]. False, some of the tile's results
/// written, when one of its rays cannot be traced (is_traceable): the caller finds which. The
/// rays' shared [tmin, tmax] must not be empty.
bool occlude_array_tile(const AnyAccel& accel, const RayImage& image, const ImageTile& tile, std::uint8_t* out,
                        StreamTraversal traversal, TriangleTest test = TriangleTest::watertight);
bool intersect_array_tile(const AnyAccel& accel, const RayImage& image, const ImageTile& tile, Hit* out,
                          StreamTraversal traversal, TriangleTest test = TriangleTest::watertight);

}  // namespace trident
