#include "render/trace.h"

#include <tbb/blocked_range.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <stdexcept>

namespace trident {
namespace {

constexpr std::size_t kTileSize = 16;

/// Runs per_pixel(x, y, index) for every pixel, tile by tile in parallel.
template <class PerPixel>
void for_each_pixel_tiled(const Camera& camera, PerPixel&& per_pixel) {
    const tbb::blocked_range2d<std::uint32_t> image(0, camera.height(), kTileSize, 0, camera.width(), kTileSize);
    tbb::parallel_for(image, [&](const tbb::blocked_range2d<std::uint32_t>& tile) {
        for (std::uint32_t y = tile.rows().begin(); y != tile.rows().end(); ++y)
            for (std::uint32_t x = tile.cols().begin(); x != tile.cols().end(); ++x)
                per_pixel(x, y, std::size_t(y) * camera.width() + x);
    });
}

}  // namespace

std::vector<Hit> trace_primary(const AnyAccel& accel, const Camera& camera, TriangleTest test) {
    std::vector<Hit> hits(std::size_t(camera.width()) * camera.height());
    trace_primary(accel, camera, hits, test);
    return hits;
}

void trace_primary(const AnyAccel& accel, const Camera& camera, std::span<Hit> hits, TriangleTest test) {
    if (hits.size() != std::size_t(camera.width()) * camera.height())
        throw std::invalid_argument("trace_primary: the hit buffer does not match the image size");
    with_triangle_test(test, [&](auto test_tag) {
        accel.visit([&](const auto& structure) {
            for_each_pixel_tiled(camera, [&](std::uint32_t x, std::uint32_t y, std::size_t i) {
                NoCounters counters;
                hits[i] = structure.template intersect<decltype(test_tag)::value>(camera.primary_ray(x, y), counters);
            });
        });
    });
}

std::vector<TraversalCounters> count_primary(const AnyAccel& accel, const Camera& camera, TriangleTest test) {
    std::vector<TraversalCounters> counts(std::size_t(camera.width()) * camera.height());
    with_triangle_test(test, [&](auto test_tag) {
        accel.visit([&](const auto& structure) {
            for_each_pixel_tiled(camera, [&](std::uint32_t x, std::uint32_t y, std::size_t i) {
                structure.template intersect<decltype(test_tag)::value>(camera.primary_ray(x, y), counts[i]);
            });
        });
    });
    return counts;
}

std::vector<std::uint8_t> trace_occlusion(const AnyAccel& accel, std::span<const Ray> rays, TriangleTest test) {
    std::vector<std::uint8_t> occluded(rays.size(), 0);
    with_triangle_test(test, [&](auto test_tag) {
        accel.visit([&](const auto& structure) {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 256), [&](const auto& range) {
                for (std::size_t i = range.begin(); i != range.end(); ++i) {
                    if (!(rays[i].tmax > rays[i].tmin)) continue;
                    NoCounters counters;
                    occluded[i] = structure.template occluded<decltype(test_tag)::value>(rays[i], counters);
                }
            });
        });
    });
    return occluded;
}

}  // namespace trident
