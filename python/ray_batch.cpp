#include "ray_batch.h"

#include <fmt/format.h>
#include <immintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "render/image_tiles.h"
#include "render/stream_packets.h"

namespace trident {

namespace {

// A list of rays is traced in rows of this many: the chunk a stream of rays is cut into for the
// threads (render/stream_packets.h).
constexpr auto kListChunkRays = std::uint32_t(kStreamChunkRays);
constexpr std::size_t kNoRay = std::numeric_limits<std::size_t>::max();

std::size_t ceil_div(std::size_t a, std::size_t b) { return (a + b - 1) / b; }

bool is_image(const RayArrays& rays) { return rays.rows > 1; }

/// The batch as the image of rays the stream kernels trace: an image of rays as it is, a list cut
/// into rows of kListChunkRays traced in runs of consecutive rays. Results are streamed when asked
/// and aligned for it.
template <class Result>
RayImage ray_image(const RayArrays& rays, BatchTraversal traversal, const Result* out) {
    const bool stream_results =
        traversal.stream_results && reinterpret_cast<std::uintptr_t>(out) % alignof(__m128) == 0;
    if (!is_image(rays))
        return {.rays = rays.strided, .width = kListChunkRays, .runs = true, .stream_results = stream_results};
    if (rays.columns > std::numeric_limits<std::uint32_t>::max())
        throw std::invalid_argument("ray batch: an image of rays is at most 2^32 - 1 columns wide");
    return {.rays = rays.strided, .width = std::uint32_t(rays.columns), .stream_results = stream_results};
}

/// The tiles the threads share: an image's 16x16 tiles row-major, as the renderer's
/// (render/image_tiles.h), or a list's rows of kListChunkRays, a tile each. With the next tile's
/// prefetch, tiles instead of bands of whole tile rows (left from when a pass of its own checked
/// the rays) took Teapot's, Bunny's and Sponza's 16-lane batches at two threads from 1.10, 1.09
/// and 1.08x the renderer's time to 1.07, 1.08 and 1.04x.
std::size_t tile_count(const RayArrays& rays) {
    if (!is_image(rays)) return ceil_div(rays.size(), kListChunkRays);
    return ceil_div(rays.rows, kRenderTileSize) * ceil_div(rays.columns, kRenderTileSize);
}

ImageTile tile_at(const RayArrays& rays, std::size_t t) {
    if (!is_image(rays))
        return {0, std::uint32_t(t),
                std::uint32_t(std::min<std::size_t>(rays.size() - t * kListChunkRays, kListChunkRays)),
                std::uint32_t(t + 1)};
    const std::size_t across = ceil_div(rays.columns, kRenderTileSize);
    const auto x0 = std::uint32_t(t % across * kRenderTileSize), y0 = std::uint32_t(t / across * kRenderTileSize);
    return {x0, y0, std::uint32_t(std::min<std::size_t>(x0 + kRenderTileSize, rays.columns)),
            std::uint32_t(std::min<std::size_t>(y0 + kRenderTileSize, rays.rows))};
}

/// per_tile(tile, t) for every tile on `traversal.threads` threads.
template <class PerTile>
void for_each_tile(const RayArrays& rays, BatchTraversal traversal, PerTile&& per_tile) {
    const int threads = traversal.threads > 0 ? traversal.threads : tbb::info::default_concurrency();
    tbb::task_arena arena(threads);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tile_count(rays)), [&](const auto& range) {
            for (std::size_t t = range.begin(); t != range.end(); ++t) per_tile(tile_at(rays, t), t);
        });
    });
}

/// The rays that cannot be traced (is_traceable): each tile's first noted, the batch's first
/// reported.
class UntraceableRays {
public:
    void note_first_in(const RayImage& image, const ImageTile& tile) {
        // Row-major, so the tile's first found is its lowest.
        for (std::uint32_t y = tile.y0; y != tile.y1; ++y)
            for (std::uint32_t x = tile.x0; x != tile.x1; ++x) {
                const std::size_t i = image.index(x, y);
                if (is_traceable(image.rays.ray(i))) continue;
                std::size_t seen = first_.load();
                while (i < seen && !first_.compare_exchange_weak(seen, i)) {
                }
                return;
            }
    }

    void throw_if_any() const {
        if (const std::size_t bad = first_.load(); bad != kNoRay)
            throw std::invalid_argument(
                fmt::format("ray {}: the origin or the direction is not finite, or the direction is zero", bad));
    }

private:
    std::atomic<std::size_t> first_{kNoRay};
};

/// One result per ray at its position in `out`, the rays read in place and traced tile by tile by
/// trace_tile(image, tile, out) (ray_stream.h's array tiles). A batch whose rays share an empty
/// [tmin, tmax] traces nothing: every result is a miss, once its rays are checked.
template <class Result, class TraceTile>
void trace_tiles(const RayArrays& rays, std::span<Result> out, BatchTraversal traversal, TraceTile&& trace_tile) {
    if (out.size() != rays.size()) throw std::invalid_argument("ray batch: one result per ray is needed");
    const RayImage image = ray_image(rays, traversal, out.data());
    UntraceableRays untraceable;
    if (!(rays.strided.tmin < rays.strided.tmax)) {
        for_each_tile(rays, traversal,
                      [&](const ImageTile& tile, std::size_t) { untraceable.note_first_in(image, tile); });
        untraceable.throw_if_any();
        std::fill(out.begin(), out.end(), Result{});
        return;
    }
    const std::size_t tiles = tile_count(rays);
    for_each_tile(rays, traversal, [&](const ImageTile& tile, std::size_t t) {
        if (t + 1 < tiles) prefetch_tile(image, tile_at(rays, t + 1));
        // A tile stops at its first packet with a ray that cannot be traced: the batch fails anyway.
        if (!trace_tile(image, tile, out.data())) untraceable.note_first_in(image, tile);
        if (image.stream_results) _mm_sfence();  // the tile's streaming stores seen before the batch returns
    });
    untraceable.throw_if_any();
}

/// The tile's ray positions in the order a list of them is traced: packet block by packet block
/// (the renderer's PrimaryBlock lanes: block rows top down, lanes row-major inside a block), a
/// list's row in runs. Where the image's edge cuts a block, the list's packet takes the next
/// block's rays too.
void order_tile(const RayImage& image, const ImageTile& tile, std::size_t lanes, std::vector<std::size_t>& index) {
    index.clear();
    const auto [block_width, block_height] = lanes >= 4 ? image.block(lanes) : std::pair{1u, 1u};
    for (std::uint32_t by = tile.y0; by < tile.y1; by += block_height)
        for (std::uint32_t bx = tile.x0; bx < tile.x1; bx += block_width)
            for (std::uint32_t y = by; y < std::min(by + block_height, tile.y1); ++y)
                for (std::uint32_t x = bx; x < std::min(bx + block_width, tile.x1); ++x)
                    index.push_back(image.index(x, y));
}

StreamTraversal stream_traversal(BatchTraversal traversal) {
    return {traversal.width, PacketGrouping::in_order, SlabTest::robust};
}

}  // namespace

void intersect_batch(const AnyAccel& accel, const RayArrays& rays, std::span<Hit> hits, BatchTraversal traversal) {
    trace_tiles(rays, hits, traversal, [&](const RayImage& image, const ImageTile& tile, Hit* out) {
        return intersect_array_tile(accel, image, tile, out, stream_traversal(traversal));
    });
}

void occluded_batch(const AnyAccel& accel, const RayArrays& rays, std::span<std::uint8_t> occluded,
                    BatchTraversal traversal) {
    trace_tiles(rays, occluded, traversal, [&](const RayImage& image, const ImageTile& tile, std::uint8_t* out) {
        return occlude_array_tile(accel, image, tile, out, stream_traversal(traversal));
    });
}

void count_hits_batch(const AnyAccel& accel, const RayArrays& rays, std::span<std::int32_t> counts,
                      BatchTraversal traversal) {
    if (counts.size() != rays.size()) throw std::invalid_argument("ray batch: one result per ray is needed");
    const RayImage image = ray_image(rays, traversal, counts.data());
    UntraceableRays untraceable;
    for_each_tile(rays, traversal, [&](const ImageTile& tile, std::size_t) {
        // The tile's rays copied into a list, in packet order: each round moves every ray's tmin.
        std::vector<std::size_t> index;
        order_tile(image, tile, lane_count(traversal.width), index);
        std::vector<Ray> tile_rays(index.size());
        for (std::size_t k = 0; k < index.size(); ++k) {
            tile_rays[k] = rays.ray(index[k]);
            if (!is_traceable(tile_rays[k])) return untraceable.note_first_in(image, tile);
        }
        std::vector<std::int32_t> tile_counts(index.size(), 0);
        std::vector<Hit> hits(index.size());
        // Each round's t is strictly past the last (a hit needs tmin <= t), so a ray ends after at
        // most as many rounds as there are triangles; a ray that missed gets tmin = +inf and is skipped.
        for (bool any_hit = true; any_hit;) {
            any_hit = false;
            intersect_stream(accel, tile_rays, hits, stream_traversal(traversal));
            for (std::size_t k = 0; k < tile_rays.size(); ++k) {
                any_hit |= hits[k].is_hit();
                tile_counts[k] += hits[k].is_hit() ? 1 : 0;
                tile_rays[k].tmin = hits[k].is_hit() ? std::nextafter(hits[k].t, kInfinity) : kInfinity;
            }
        }
        for (std::size_t k = 0; k < index.size(); ++k) counts[index[k]] = tile_counts[k];
    });
    untraceable.throw_if_any();
}

void contains_batch(const AnyAccel& accel, const float* points, std::size_t count, std::span<std::uint8_t> inside,
                    BatchTraversal traversal) {
    if (inside.size() != count) throw std::invalid_argument("contains: one result per point is needed");
    // Directions far from the axes and the diagonals, which closed meshes' edges and vertices favour.
    static constexpr float kDirections[3][3] = {
        {0.4135f, 0.6789f, 0.6068f}, {-0.7127f, 0.2213f, -0.6659f}, {0.1874f, -0.9130f, 0.3624f}};
    auto crossings = [&](const float* origins, std::size_t n, const float* direction) {
        std::vector<std::int32_t> counts(n);
        count_hits_batch(
            accel,
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
