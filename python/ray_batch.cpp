#include "ray_batch.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include "render/image_tiles.h"

namespace trident {

namespace {

// Runs of consecutive rays in a list, as ray_stream.cpp cuts its parallel streams.
constexpr std::size_t kListChunkRays = 1024;
constexpr std::size_t kNoRay = std::numeric_limits<std::size_t>::max();

std::size_t ceil_div(std::size_t a, std::size_t b) { return (a + b - 1) / b; }

bool is_image(const RayArrays& rays) { return rays.rows > 1; }

// An image's chunk is a band of whole tile rows: its rays lie in one run of the caller's arrays,
// which the check reads front to back (the hardware prefetches that; single 16x16 tiles, 16 short
// runs apart, took the check as long as the packets' own reads) and the packets then find in cache.
std::size_t chunk_count(const RayArrays& rays) {
    return is_image(rays) ? ceil_div(rays.rows, kRenderTileSize) : ceil_div(rays.size(), kListChunkRays);
}

/// The positions [first, last) of chunk c's rays in the batch.
std::pair<std::size_t, std::size_t> chunk_range(const RayArrays& rays, std::size_t c) {
    const std::size_t run = is_image(rays) ? kRenderTileSize * rays.columns : kListChunkRays;
    return {c * run, std::min(rays.size(), (c + 1) * run)};
}

/// The rays of one chunk: their positions in the batch in the order the stream packs them and, when
/// they are not traced in place (`gathered`), copied out of the caller's arrays.
struct Chunk {
    std::vector<std::size_t> index;
    bool gathered = false;
    std::vector<Ray> rays;
};

/// Chunk `c`'s ray positions in the order they are traced: a list's run, or a band's tiles left to
/// right, each tile's pixels packet block by packet block (the renderer's PrimaryBlock lanes: block
/// rows top down, lanes row-major inside a block). Where the image's edge cuts a block, the stream
/// fills the packet with the next block's rays.
void order_chunk(const RayArrays& rays, std::size_t lanes, std::size_t c, std::vector<std::size_t>& index) {
    index.clear();
    const auto [first, last] = chunk_range(rays, c);
    if (!is_image(rays)) {
        for (std::size_t i = first; i < last; ++i) index.push_back(i);
        return;
    }
    const auto [block_width, block_height] = lanes >= 4 ? packet_block(lanes) : std::pair{1u, 1u};
    const std::size_t y0 = first / rays.columns, y1 = last / rays.columns;
    for (std::size_t x0 = 0; x0 < rays.columns; x0 += kRenderTileSize) {
        const std::size_t x1 = std::min(x0 + kRenderTileSize, rays.columns);
        for (std::size_t by = y0; by < y1; by += block_height)
            for (std::size_t bx = x0; bx < x1; bx += block_width)
                for (std::size_t y = by; y < std::min<std::size_t>(by + block_height, y1); ++y)
                    for (std::size_t x = bx; x < std::min<std::size_t>(bx + block_width, x1); ++x)
                        index.push_back(y * rays.columns + x);
    }
}

bool is_traceable(const Ray& ray) {
    return is_finite(ray.origin) && is_finite(ray.dir) && dot(ray.dir, ray.dir) > 0.0f;
}

/// per_chunk(Chunk&) over every chunk on `traversal.threads` threads. With `gather`, a chunk whose
/// rays are all traceable is traced in place (chunk.gathered); otherwise its rays are copied, and
/// one that cannot be traced gets tmax = -inf, which the stream skips. The first such ray is
/// reported once all are done.
template <class PerChunk>
void for_each_chunk(const RayArrays& rays, BatchTraversal traversal, bool gather, PerChunk&& per_chunk) {
    std::atomic<std::size_t> first_bad{kNoRay};
    const int threads = traversal.threads > 0 ? traversal.threads : tbb::info::default_concurrency();
    gather = gather && rays.strided.tmin < rays.strided.tmax;
    tbb::task_arena arena(threads);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunk_count(rays)), [&](const auto& range) {
            Chunk chunk;
            for (std::size_t c = range.begin(); c != range.end(); ++c) {
                order_chunk(rays, lane_count(traversal.width), c, chunk.index);
                bool all_traceable = true;
                const auto [first, last] = chunk_range(rays, c);
                for (std::size_t i = first; i < last; ++i) {
                    if (is_traceable(rays.ray(i))) continue;
                    all_traceable = false;
                    std::size_t seen = first_bad.load();
                    while (i < seen && !first_bad.compare_exchange_weak(seen, i)) {
                    }
                }
                chunk.gathered = gather && all_traceable;
                if (!chunk.gathered) {
                    chunk.rays.resize(chunk.index.size());
                    for (std::size_t k = 0; k < chunk.index.size(); ++k) {
                        chunk.rays[k] = rays.ray(chunk.index[k]);
                        if (!is_traceable(chunk.rays[k])) chunk.rays[k].tmax = -kInfinity;
                    }
                }
                per_chunk(chunk);
            }
        });
    });
    if (const std::size_t bad = first_bad.load(); bad != kNoRay)
        throw std::invalid_argument(
            fmt::format("ray {}: the origin or the direction is not finite, or the direction is zero", bad));
}

StreamTraversal stream_traversal(BatchTraversal traversal) {
    return {traversal.width, PacketGrouping::in_order, SlabTest::robust};
}

/// Each chunk's rays traced into one result per ray at the rays' positions in `out`: in place by
/// trace_gathered(strided rays, positions, out) where the chunk allows it, else by
/// trace_list(rays, results) on a copy (trace_list may change the rays), the results then
/// written to the rays' positions. Without trace_gathered every chunk is copied.
template <class Result, class TraceList, class TraceGathered = std::nullptr_t>
void trace_chunks(const RayArrays& rays, std::span<Result> out, BatchTraversal traversal, TraceList&& trace_list,
                  TraceGathered&& trace_gathered = nullptr) {
    if (out.size() != rays.size()) throw std::invalid_argument("ray batch: one result per ray is needed");
    constexpr bool kGather = !std::is_same_v<std::decay_t<TraceGathered>, std::nullptr_t>;
    for_each_chunk(rays, traversal, kGather, [&](Chunk& chunk) {
        if constexpr (kGather) {
            if (chunk.gathered) return trace_gathered(rays.strided, std::span<const std::size_t>(chunk.index), out);
        }
        thread_local std::vector<Result> results;
        results.assign(chunk.rays.size(), Result{});
        trace_list(chunk.rays, std::span<Result>(results));
        for (std::size_t k = 0; k < chunk.index.size(); ++k) out[chunk.index[k]] = results[k];
    });
}

}  // namespace

void intersect_batch(const AnyAccel& accel, const RayArrays& rays, std::span<Hit> hits, BatchTraversal traversal) {
    trace_chunks(
        rays, hits, traversal,
        [&](const std::vector<Ray>& chunk_rays, std::span<Hit> chunk_hits) {
            intersect_stream(accel, chunk_rays, chunk_hits, stream_traversal(traversal));
        },
        [&](const StridedRays& strided, std::span<const std::size_t> order, std::span<Hit> out) {
            intersect_stream(accel, strided, order, out, stream_traversal(traversal));
        });
}

void occluded_batch(const AnyAccel& accel, const RayArrays& rays, std::span<std::uint8_t> occluded,
                    BatchTraversal traversal) {
    trace_chunks(
        rays, occluded, traversal,
        [&](const std::vector<Ray>& chunk_rays, std::span<std::uint8_t> chunk_occluded) {
            occlude_stream(accel, chunk_rays, chunk_occluded, stream_traversal(traversal));
        },
        [&](const StridedRays& strided, std::span<const std::size_t> order, std::span<std::uint8_t> out) {
            occlude_stream(accel, strided, order, out, stream_traversal(traversal));
        });
}

void count_hits_batch(const AnyAccel& accel, const RayArrays& rays, std::span<std::int32_t> counts,
                      BatchTraversal traversal) {
    trace_chunks(rays, counts, traversal, [&](std::vector<Ray>& chunk_rays, std::span<std::int32_t> chunk_counts) {
        std::vector<Hit> hits(chunk_rays.size());
        // Each round's t is strictly past the last (a hit needs tmin <= t), so a ray ends after at
        // most as many rounds as there are triangles; a ray that missed gets tmin = +inf and is skipped.
        for (bool any_hit = true; any_hit;) {
            any_hit = false;
            intersect_stream(accel, chunk_rays, hits, stream_traversal(traversal));
            for (std::size_t k = 0; k < chunk_rays.size(); ++k) {
                any_hit |= hits[k].is_hit();
                chunk_counts[k] += hits[k].is_hit() ? 1 : 0;
                chunk_rays[k].tmin = hits[k].is_hit() ? std::nextafter(hits[k].t, kInfinity) : kInfinity;
            }
        }
    });
}

void contains_batch(const AnyAccel& accel, const float* points, std::size_t count, std::span<std::uint8_t> inside,
                    BatchTraversal traversal) {
    if (inside.size() != count) throw std::invalid_argument("contains: one result per point is needed");
    // Directions far from the axes and the diagonals, which closed meshes' edges and vertices favour.
    static constexpr float kDirections[3][3] = {
        {0.4135f, 0.6789f, 0.6068f}, {-0.7127f, 0.2213f, -0.6659f}, {0.1874f, -0.9130f, 0.3624f}};
    auto crossings = [&](const float* origins, std::size_t n, const float* direction) {
        std::vector<std::int32_t> counts(n);
        count_hits_batch(accel,
                         RayArrays{.strided = {.origins = origins, .directions = direction, .direction_stride = 0}, .columns = n},
                         counts, traversal);
        return counts;
    };
    const std::vector<std::int32_t> first = crossings(points, count, kDirections[0]);
    const std::vector<std::int32_t> second = crossings(points, count, kDirections[1]);
    std::vector<std::size_t> undecided;
    std::vector<float> undecided_points;
    for (std::size_t i = 0; i < count; ++i) {
        inside[i] = first[i] % 2;
        if (first[i] % 2 == second[i] % 2) continue;
        undecided.push_back(i);
        undecided_points.insert(undecided_points.end(), points + 3 * i, points + 3 * i + 3);
    }
    if (undecided.empty()) return;
    const std::vector<std::int32_t> third = crossings(undecided_points.data(), undecided.size(), kDirections[2]);
    for (std::size_t k = 0; k < undecided.size(); ++k) inside[undecided[k]] = third[k] % 2;
}

}  // namespace trident
