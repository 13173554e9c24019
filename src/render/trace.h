#pragma once
// Tracing the primary rays of a camera image over all cores; lists of other rays go through
// ray_stream.h. Image tiles of 16x16 pixels are spread over oneTBB's threads; the caller sets the
// thread count (tbb::global_control).
#include <span>
#include <vector>

#include "accel/any_accel.h"
#include "camera/camera.h"
#include "core/intersect_triangle.h"
#include "core/slab_test.h"
#include "core/traversal_variant.h"
#include "render/image_tiles.h"
#include "simd/width.h"

namespace trident {

/// Whether trace_primary first tests each tile's frustum against the structure's top boxes and
/// writes misses, without making its rays, for a tile none of whose rays can reach them
/// (render/tile_frustum.h; the hits are the same either way), or traces every ray (`off`: what
/// the structure's walks cost per ray, as a ray-by-ray interface such as Embree's must).
enum class TileCulling { frustum, off };

/// Closest hit of every primary ray, row-major from the top row. With a packet width, rays go as
/// packets of 2x2 (4 lanes), 4x2 (8) or 4x4 (16) pixels; lanes past the image edge are inactive.
/// Throws std::runtime_error when the width is not runnable here or the structure has no packets.
/// `slabs` picks the structures' robust (default) or fast box tests (core/slab_test.h).
std::vector<Hit> trace_primary(const AnyAccel& accel, const Camera& camera,
                               TriangleTest test = TriangleTest::watertight, SimdWidth width = SimdWidth::scalar,
                               SlabTest slabs = SlabTest::robust, TileCulling culling = TileCulling::frustum);
/// The same into a buffer of width x height hits the caller owns, so repeated timed traces
/// (trident-bench) measure tracing, not allocating. Throws std::invalid_argument on a wrong size.
void trace_primary(const AnyAccel& accel, const Camera& camera, std::span<Hit> hits,
                   TriangleTest test = TriangleTest::watertight, SimdWidth width = SimdWidth::scalar,
                   SlabTest slabs = SlabTest::robust, TileCulling culling = TileCulling::frustum);
/// Whether trace_primary can run this structure at this width here (scalar always; a packet width
/// needs the CPU's instruction set and the structure's packet traversal), so the benchmark skips
/// what trace_primary would refuse.
bool has_packet_traversal(const AnyAccel& accel, SimdWidth width);

/// The same rays traced with counters on: nodes visited and triangles tested per pixel.
std::vector<TraversalCounters> count_primary(const AnyAccel& accel, const Camera& camera,
                                             TriangleTest test = TriangleTest::watertight,
                                             SlabTest slabs = SlabTest::robust);

}  // namespace trident
