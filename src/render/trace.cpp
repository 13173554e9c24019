#include "render/trace.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <array>
#include <stdexcept>

#include "simd/packet.h"

namespace trident {
namespace {

// Tiles are a multiple of every packet block, so blocks are cut only at the image's edges.
constexpr std::uint32_t kTileSize = 16;

using Tile = tbb::blocked_range2d<std::uint32_t>;

/// Runs per_tile(tile) over the image's tiles in parallel.
template <class PerTile>
void for_each_tile(const Camera& camera, PerTile&& per_tile) {
    tbb::parallel_for(Tile(0, camera.height(), kTileSize, 0, camera.width(), kTileSize), per_tile);
}

template <class PerPixel>
void for_each_pixel_tiled(const Camera& camera, PerPixel&& per_pixel) {
    for_each_tile(camera, [&](const Tile& tile) {
        for (std::uint32_t y = tile.rows().begin(); y != tile.rows().end(); ++y)
            for (std::uint32_t x = tile.cols().begin(); x != tile.cols().end(); ++x)
                per_pixel(x, y, std::size_t(y) * camera.width() + x);
    });
}

/// Scalar always; a packet width when the structure has a packet traversal.
template <SimdWidth W, class Structure>
constexpr bool can_trace_at() {
    if constexpr (W == SimdWidth::scalar) return true;
    else return PacketTraversable<Structure, ArchOf<W>>;
}

[[noreturn]] void throw_no_packets(const AnyAccel& accel, SimdWidth width) {
    throw std::runtime_error(fmt::format("--simd {} with --accel {}: packet traversal not built yet", to_string(width),
                                         to_string(accel.kind())));
}

/// Primary rays of one tile as packets of the structure's closest-hit packet traversal.
template <TriangleTest Test, SlabTest Slabs, class Arch, class Structure>
void trace_tile_packets(const Structure& structure, const Camera& camera, const Tile& tile, std::span<Hit> out) {
    constexpr std::size_t kLanes = RayPacket<Arch>::width;
    constexpr auto kBlock = packet_block(kLanes);
    std::array<Ray, kLanes> rays;
    std::array<std::size_t, kLanes> pixel;
    std::array<Hit, kLanes> hits;
    for (std::uint32_t y0 = tile.rows().begin(); y0 < tile.rows().end(); y0 += kBlock.second) {
        for (std::uint32_t x0 = tile.cols().begin(); x0 < tile.cols().end(); x0 += kBlock.first) {
            std::size_t lanes = 0;
            for (std::uint32_t y = y0; y < y0 + kBlock.second && y < tile.rows().end(); ++y)
                for (std::uint32_t x = x0; x < x0 + kBlock.first && x < tile.cols().end(); ++x) {
                    rays[lanes] = camera.primary_ray(x, y);
                    pixel[lanes++] = std::size_t(y) * camera.width() + x;
                }
            const RayPacket<Arch> packet(std::span<const Ray>(rays.data(), lanes));
            HitPacket<Arch> packet_hits(packet);
            NoCounters counters;
            structure.template intersect<Test, Slabs>(packet, packet_hits, counters);
            packet_hits.store(std::span<Hit>(hits.data(), lanes));
            for (std::size_t i = 0; i < lanes; ++i) out[pixel[i]] = hits[i];
        }
    }
}

}  // namespace

std::vector<Hit> trace_primary(const AnyAccel& accel, const Camera& camera, TriangleTest test, SimdWidth width,
                               SlabTest slabs) {
    std::vector<Hit> hits(std::size_t(camera.width()) * camera.height());
    trace_primary(accel, camera, hits, test, width, slabs);
    return hits;
}

void trace_primary(const AnyAccel& accel, const Camera& camera, std::span<Hit> hits, TriangleTest test, SimdWidth width,
                   SlabTest slabs) {
    if (hits.size() != std::size_t(camera.width()) * camera.height())
        throw std::invalid_argument("trace_primary: the hit buffer does not match the image size");
    with_traversal_variant(test, slabs, [&](auto test_tag, auto slabs_tag) {
        constexpr TriangleTest Test = decltype(test_tag)::value;
        constexpr SlabTest Slabs = decltype(slabs_tag)::value;
        accel.visit([&](const auto& structure) {
            using Structure = std::decay_t<decltype(structure)>;
            dispatch_width(width, [&]<SimdWidth W>() {
                if constexpr (W == SimdWidth::scalar) {
                    for_each_pixel_tiled(camera, [&](std::uint32_t x, std::uint32_t y, std::size_t i) {
                        NoCounters counters;
                        hits[i] = structure.template intersect<Test, Slabs>(camera.primary_ray(x, y), counters);
                    });
                } else if constexpr (PacketTraversable<Structure, ArchOf<W>>) {
                    for_each_tile(camera, [&](const Tile& tile) {
                        trace_tile_packets<Test, Slabs, ArchOf<W>>(structure, camera, tile, hits);
                    });
                } else {
                    throw_no_packets(accel, W);
                }
            });
        });
    });
}

bool has_packet_traversal(const AnyAccel& accel, SimdWidth width) {
    if (width == SimdWidth::scalar) return true;
    if (!is_runnable(width)) return false;
    return accel.visit([&](const auto& structure) {
        using Structure = std::decay_t<decltype(structure)>;
        return dispatch_width(width, [&]<SimdWidth W>() {
            if constexpr (W == SimdWidth::scalar) return true;
            else return PacketTraversable<Structure, ArchOf<W>>;
        });
    });
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
