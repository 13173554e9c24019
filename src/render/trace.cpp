#include "render/trace.h"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "render/image_tiles.h"
#include "render/render_kernels.h"
#include "render/tile_frustum.h"

namespace trident {
namespace {

template <class PerPixel>
void for_each_pixel_of(const Camera& camera, const ImageTile& tile, PerPixel&& per_pixel) {
    for (std::uint32_t y = tile.y0; y != tile.y1; ++y)
        for (std::uint32_t x = tile.x0; x != tile.x1; ++x) per_pixel(x, y, std::size_t(y) * camera.width() + x);
}

template <class PerPixel>
void for_each_pixel_tiled(const Camera& camera, PerPixel&& per_pixel) {
    for_each_image_tile(camera, [&](const ImageTile& tile) { for_each_pixel_of(camera, tile, per_pixel); });
}

/// per_tile(tile) for each image tile, except, with TileCulling::frustum, the tiles none of whose
/// rays can reach the structure's top boxes (TileCuller), whose pixels get misses instead.
template <class Structure, class PerTile>
void for_each_tile_to_trace(const Structure& structure, const Camera& camera, std::span<Hit> hits, TileCulling culling,
                            PerTile&& per_tile) {
    const std::optional<TileCuller> culler =
        culling == TileCulling::frustum ? std::optional<TileCuller>(std::in_place, structure, camera) : std::nullopt;
    for_each_image_tile(camera, [&](const ImageTile& tile) {
        if (!culler || culler->may_hit(tile)) return per_tile(tile);
        for (std::uint32_t y = tile.y0; y != tile.y1; ++y)
            std::fill_n(hits.begin() + std::ptrdiff_t(std::size_t(y) * camera.width() + tile.x0), tile.x1 - tile.x0,
                        Hit{});
    });
}

}  // namespace

std::vector<Hit> trace_primary(const AnyAccel& accel, const Camera& camera, TriangleTest test, SimdWidth width,
                               SlabTest slabs, TileCulling culling) {
    std::vector<Hit> hits(std::size_t(camera.width()) * camera.height());
    trace_primary(accel, camera, hits, test, width, slabs, culling);
    return hits;
}

void trace_primary(const AnyAccel& accel, const Camera& camera, std::span<Hit> hits, TriangleTest test, SimdWidth width,
                   SlabTest slabs, TileCulling culling) {
    if (hits.size() != std::size_t(camera.width()) * camera.height())
        throw std::invalid_argument("trace_primary: the hit buffer does not match the image size");
    // Single rays take the variant as template arguments; the packet kernels take it at run time.
    if (width == SimdWidth::scalar) {
        // The portable build's single rays run in the widest kernel file the CPU (and the cap) allow.
        const bool in_kernel_file = in_widest_kernel_file([&]<SimdWidth File>() {
            accel.visit([&](const auto& structure) {
                using Structure = std::decay_t<decltype(structure)>;
                for_each_tile_to_trace(structure, camera, hits, culling, [&](const ImageTile& tile) {
                    SingleRayKernels<Structure, File>::trace_primary_tile(structure, camera, tile, hits, test, slabs);
                });
            });
        });
        if (in_kernel_file) return;
        with_traversal_variant(test, slabs, [&](auto test_tag, auto slabs_tag) {
            accel.visit([&](const auto& structure) {
                for_each_tile_to_trace(structure, camera, hits, culling, [&](const ImageTile& tile) {
                    for_each_pixel_of(camera, tile, [&](std::uint32_t x, std::uint32_t y, std::size_t i) {
                        NoCounters counters;
                        hits[i] = structure.template intersect<decltype(test_tag)::value, decltype(slabs_tag)::value>(
                            camera.primary_ray(x, y), counters);
                    });
                });
            });
        });
        return;
    }
    accel.visit([&](const auto& structure) {
        using Structure = std::decay_t<decltype(structure)>;
        // In the portable build, in the widest kernel file the CPU (and the cap) allow.
        dispatch_packet_width(width, [&]<SimdWidth W, SimdWidth File>() {
            for_each_tile_to_trace(structure, camera, hits, culling, [&](const ImageTile& tile) {
                RenderKernels<Structure, W, File>::trace_primary_tile(structure, camera, tile, hits,
                                                                      {.test = test, .slabs = slabs});
            });
        });
    });
}

bool has_packet_traversal(const AnyAccel&, SimdWidth width) {
    // Every structure AnyAccel holds has its packet traversals in each width's kernel files.
    return width == SimdWidth::scalar || is_runnable(width);
}

std::vector<TraversalCounters> count_primary(const AnyAccel& accel, const Camera& camera, TriangleTest test,
                                             SlabTest slabs) {
    std::vector<TraversalCounters> counts(std::size_t(camera.width()) * camera.height());
    with_traversal_variant(test, slabs, [&](auto test_tag, auto slabs_tag) {
        accel.visit([&](const auto& structure) {
            for_each_pixel_tiled(camera, [&](std::uint32_t x, std::uint32_t y, std::size_t i) {
                structure.template intersect<decltype(test_tag)::value, decltype(slabs_tag)::value>(
                    camera.primary_ray(x, y), counts[i]);
            });
        });
    });
    return counts;
}

}  // namespace trident
