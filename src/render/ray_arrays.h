#pragma once
// Rays read where the caller keeps them (numpy's arrays, for the Python module), and the image of
// rays the stream kernels trace by tiles (ray_stream.h), as the renderer traces its primary rays.

#include <cstddef>
#include <cstdint>
#include <utility>

#include "core/prefetch.h"
#include "core/ray.h"
#include "render/image_tiles.h"

namespace trident {

/// Ray i's origin is origins[i * origin_stride + 0..2], its direction the same in `directions`;
/// a stride of 0 gives every ray the same origin (or direction). All share [tmin, tmax].
struct StridedRays {
    const float* origins = nullptr;
    std::size_t origin_stride = 3;
    const float* directions = nullptr;
    std::size_t direction_stride = 3;
    float tmin = 0.0f;
    float tmax = kInfinity;

    Ray ray(std::size_t i) const {
        const float* o = origins + i * origin_stride;
        const float* d = directions + i * direction_stride;
        return Ray{{o[0], o[1], o[2]}, {d[0], d[1], d[2]}, tmin, tmax};
    }
};

/// Whether a ray can be traced at all: its origin and direction finite, and its direction's
/// squared length, which the tests divide by in effect, not zero.
inline bool is_traceable(const Ray& ray) {
    return is_finite(ray.origin) && is_finite(ray.dir) && dot(ray.dir, ray.dir) > 0.0f;
}

/// Rays in arrays seen as an image: ray (x, y) is rays.ray(y * width + x). A packet takes a block
/// of packet_block(lanes) pixels, as the renderer's primary packets do, or, when the rays are a
/// list cut into rows (`runs`), `lanes` consecutive rays of a row.
///
/// With `stream_results`, closest hits are written with streaming stores, which bypass the caches
/// and do not read the line they write (simd/hit_lanes.h): for a batch too large to stay cached, into
/// memory kept between batches (python/result_memory.h). The results must be 16-byte aligned, and
/// the writing thread fences (_mm_sfence) before another reads them.
struct RayImage {
    StridedRays rays;
    std::uint32_t width = 0;
    bool runs = false;
    bool stream_results = false;

    std::size_t index(std::uint32_t x, std::uint32_t y) const { return std::size_t(y) * width + x; }
    std::pair<std::uint32_t, std::uint32_t> block(std::size_t lanes) const {
        return runs ? std::pair{std::uint32_t(lanes), 1u} : packet_block(lanes);
    }
};

/// Asks the memory system for the tile's rays ahead of their use: the tile after the one being
/// traced, whose rows lie an image row apart. With __builtin_prefetch this function compiled to
/// nothing (core/prefetch.h says why); once it ran, the module's 16-lane BVH batches at 1920x1080
/// took Teapot 1.46x, Room 1.23x and Gallery 1.13x less time (one thread; scalar rays unchanged).
inline void prefetch_tile(const RayImage& image, const ImageTile& tile) {
    constexpr std::size_t kLine = 64;
    for (std::uint32_t y = tile.y0; y != tile.y1; ++y) {
        for (const auto& [base, stride] : {std::pair{image.rays.origins, image.rays.origin_stride},
                                           std::pair{image.rays.directions, image.rays.direction_stride}}) {
            const char* first = reinterpret_cast<const char*>(base + image.index(tile.x0, y) * stride);
            const char* last = reinterpret_cast<const char*>(base + image.index(tile.x1 - 1, y) * stride + 2);
            for (const char* p = first; p <= last; p += kLine) prefetch_line(p);
            prefetch_line(last);
        }
    }
}

/// The tile's rays one at a time, row by row, out[image.index(x, y)] = trace(ray); false at the
/// first ray that cannot be traced, the results before it written. Normal stores, whatever
/// image.stream_results says: streamed, a 1920x1080 batch of Bunny's single rays took 7% longer
/// (two threads, A/B).
template <class Result, class Trace>
bool trace_tile_singly(const RayImage& image, const ImageTile& tile, Result* out, Trace&& trace) {
    for (std::uint32_t y = tile.y0; y != tile.y1; ++y)
        for (std::uint32_t x = tile.x0; x != tile.x1; ++x) {
            const std::size_t i = image.index(x, y);
            const Ray ray = image.rays.ray(i);
            if (!is_traceable(ray)) return false;
            out[i] = trace(ray);
        }
    return true;
}

}  // namespace trident
