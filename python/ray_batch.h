#pragma once
// Queries over a batch of rays the caller keeps in its own float arrays (numpy's, for the Python
// module): origins and directions read in place through strides, results written straight into the
// caller's buffers. An image of rays (rows x columns) is traced as the renderer traces its primary
// rays, in 16x16 tiles whose packets take blocks of 2x2, 4x2 or 4x4 pixels (render/image_tiles.h),
// bands of tiles shared by the threads; a list of rays in runs of consecutive rays
// (render/ray_stream.h's array tiles).
#include <cstddef>
#include <cstdint>
#include <span>

#include "accel/any_accel.h"
#include "core/ray.h"
#include "render/ray_stream.h"

namespace trident {

/// A batch: where its rays lie in the caller's arrays (render/ray_arrays.h) and how many there are.
struct RayArrays {
    StridedRays strided;
    /// rows x columns rays, row-major: rows > 1 makes it an image traced in tiles.
    std::size_t rows = 1;
    std::size_t columns = 0;

    std::size_t size() const { return rows * columns; }
    Ray ray(std::size_t i) const { return strided.ray(i); }
};

/// How a batch is traced: the packet width (scalar: single rays), the threads (0: all cores), and
/// whether closest hits are written with streaming stores (RayImage::stream_results: for large
/// batches into memory kept between them, python/result_memory.h).
struct BatchTraversal {
    SimdWidth width = SimdWidth::scalar;
    int threads = 0;
    bool stream_results = false;
};

/// Every query throws std::invalid_argument, naming the first such ray, when an origin or a
/// direction is not finite or a direction is zero; such rays are never traced.
void intersect_batch(const AnyAccel& accel, const RayArrays& rays, std::span<Hit> hits, BatchTraversal traversal);
void occluded_batch(const AnyAccel& accel, const RayArrays& rays, std::span<std::uint8_t> occluded,
                    BatchTraversal traversal);
/// The surfaces each ray crosses in [tmin, tmax]: closest hits taken again just past the last one,
/// so hits at one distance (a ray through an edge both its triangles report) count once.
void count_hits_batch(const AnyAccel& accel, const RayArrays& rays, std::span<std::int32_t> counts,
                      BatchTraversal traversal);
/// Whether each point lies inside the closed mesh: odd crossings along a fixed direction, and
/// where two directions disagree (a ray grazing an edge or a vertex) a third one decides.
void contains_batch(const AnyAccel& accel, const float* points, std::size_t count, std::span<std::uint8_t> inside,
                    BatchTraversal traversal);

}  // namespace trident
