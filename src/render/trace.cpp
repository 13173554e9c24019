#include "render/trace.h"

#include <fmt/format.h>

#include <stdexcept>

#include "render/image_tiles.h"
#include "render/primary_packets.h"
#include "simd/packet.h"

namespace trident {
namespace {

template <class PerPixel>
void for_each_pixel_tiled(const Camera& camera, PerPixel&& per_pixel) {
    for_each_image_tile(camera, [&](const ImageTile& tile) {
        for (std::uint32_t y = tile.y0; y != tile.y1; ++y)
            for (std::uint32_t x = tile.x0; x != tile.x1; ++x)
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
void trace_tile_packets(const Structure& structure, const Camera& camera, const ImageTile& tile, std::span<Hit> out) {
    for_each_primary_block<Arch>(camera, tile, [&](const PrimaryBlock<Arch>& block) {
        const RayPacket<Arch> packet = block.rays();
        HitPacket<Arch> hits(packet);
        NoCounters counters;
        intersect_packet(structure, packet, hits, counters, {.test = Test, .slabs = Slabs});
        block.store(hits, tile, camera.width(), out);
    });
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
                    for_each_image_tile(camera, [&](const ImageTile& tile) {
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
