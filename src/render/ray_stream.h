#pragma once
// Tracing a list of secondary rays (shadow, ambient-occlusion, diffuse-bounce) on the calling
// thread, one at a time or as packets, cut from the list in order or by direction octant
// (stream_packets.h). Rays with tmax <= tmin are not traced: unoccluded, no hit.
#include <cstddef>
#include <cstdint>
#include <span>

#include "accel/any_accel.h"
#include "core/intersect_triangle.h"
#include "core/slab_test.h"
#include "render/stream_packets.h"
#include "simd/width.h"

namespace trident {

/// How a stream is traced: single rays (width scalar) or packets of `width` lanes grouped so, with
/// the robust or the fast slab test.
struct StreamTraversal {
    SimdWidth width = SimdWidth::scalar;
    PacketGrouping grouping = PacketGrouping::in_order;
    SlabTest slabs = SlabTest::robust;
};

/// Any-hit: occluded[i] = 1 when rays[i] hits anything in [tmin, tmax]. Throws std::runtime_error
/// when the structure has no packet traversal of that width.
void occlude_stream(const AnyAccel& accel, std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                    StreamTraversal traversal, TriangleTest test = TriangleTest::watertight);
/// Closest hit of each ray.
void intersect_stream(const AnyAccel& accel, std::span<const Ray> rays, std::span<Hit> hits, StreamTraversal traversal,
                      TriangleTest test = TriangleTest::watertight);

/// Rays read where the caller keeps them (numpy's arrays, for the Python module): ray i's origin
/// is origins[i * origin_stride + 0..2], its direction the same in `directions`; a stride of 0
/// gives every ray the same origin (or direction). All share [tmin, tmax].
struct StridedRays {
    const float* origins = nullptr;
    std::size_t origin_stride = 3;
    const float* directions = nullptr;
    std::size_t direction_stride = 3;
    float tmin = 0.0f;
    float tmax = kInfinity;

    /// Inline: the Python module reads every ray through it twice (its check, the packet).
    Ray ray(std::size_t i) const {
        const float* o = origins + i * origin_stride;
        const float* d = directions + i * direction_stride;
        return Ray{{o[0], o[1], o[2]}, {d[0], d[1], d[2]}, tmin, tmax};
    }
};

/// The rays rays.ray(order[k]) traced with their results written straight to position order[k]
/// of `occluded` or `hits`, packets taking consecutive entries of `order` (so the caller decides
/// which rays share a packet), without copying the rays into a list first. Every ray must be
/// traceable: finite, a non-zero direction, tmin < tmax; the caller checks that.
void occlude_stream(const AnyAccel& accel, const StridedRays& rays, std::span<const std::size_t> order,
                    std::span<std::uint8_t> occluded, StreamTraversal traversal,
                    TriangleTest test = TriangleTest::watertight);
void intersect_stream(const AnyAccel& accel, const StridedRays& rays, std::span<const std::size_t> order,
                      std::span<Hit> hits, StreamTraversal traversal, TriangleTest test = TriangleTest::watertight);

/// The same over all cores, the list cut into chunks of consecutive rays.
void occlude_stream_parallel(const AnyAccel& accel, std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                             StreamTraversal traversal, TriangleTest test = TriangleTest::watertight);
void intersect_stream_parallel(const AnyAccel& accel, std::span<const Ray> rays, std::span<Hit> hits,
                               StreamTraversal traversal, TriangleTest test = TriangleTest::watertight);

}  // namespace trident
