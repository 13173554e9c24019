// The renderer's packet loops and its single-ray loops (render/render_kernels.h), compiled once
// for each packet width (simd/kernel_arch.h) for every structure AnyAccel holds.
#include "render/render_kernels.h"

#include "accel/any_accel.h"
#include "core/flatten.h"
#include "core/traversal_variant.h"
#include "render/array_packets.h"
#include "render/occlude_in_order.h"
#include "render/primary_packets.h"
#include "render/stream_packets.h"
#include "simd/hit_lanes.h"
#include "simd/kernel_arch.h"
#include "simd/packet.h"

namespace trident {
namespace {

/// done(block, hits, counters) after each packet block of the tile's primary rays is traced.
template <class Arch, class Counters, class Structure, class Done>
void trace_primary_blocks(const Structure& structure, const Camera& camera, const ImageTile& tile,
                          PacketVariant variant, Done&& done) {
    for_each_primary_block<Arch>(camera, tile, [&](const PrimaryBlock<Arch>& block) {
        const RayPacket<Arch> packet = block.rays();
        HitPacket<Arch> hits(packet);
        Counters counters;
        intersect_packet(structure, packet, hits, counters, variant);
        done(block, hits, counters);
    });
}

/// The packet of the rays rays[index[0]], rays[index[1]], ... (1 to the packet's lanes, all
/// traced), read where they lie. Flattened: from the stream loop gcc called the packet's
/// constructors out of line, and Teapot's 8-lane shadow packets took 5% longer (native build).
template <class Arch>
TRIDENT_FLATTEN RayPacket<Arch> gather_packet(std::span<const Ray> rays, std::span<const std::size_t> index) {
    return RayPacket<Arch>(rays, index);
}

/// RenderKernels' stream loop: walk(index) for each packet of `Lanes` or fewer traced rays that
/// `grouping` cuts from `rays`, except the packets whose lanes would all walk alone from the root
/// (packet_walks_lanes_alone, under the structure's own switch only): their rays are marked in
/// `alone` instead. Returns whether any were.
template <std::size_t Lanes, class Structure, class Walk>
bool trace_stream_packets(const Structure& structure, std::span<const Ray> rays, PacketGrouping grouping,
                          PacketVariant variant, std::span<std::uint8_t> alone, Walk&& walk) {
    bool any_alone = false;
    for_each_stream_packet(rays, Lanes, grouping, [&](std::span<const std::size_t> index) {
        if constexpr (WalksLanesAlone<Structure>) {
            if (variant.single_ray_lanes == kDefaultSingleRayLanes && structure.packet_walks_lanes_alone(rays, index)) {
                for (const std::size_t i : index) alone[i] = 1;
                any_alone = true;
                return;
            }
        }
        walk(index);
    });
    return any_alone;
}

/// RenderKernels<Structure, Width, File> is defined in File's kernel file, for its own width or
/// (portable build, wider files) for a narrower one.
template <SimdWidth Width, SimdWidth File>
inline constexpr bool kDefinedHere = File == kKernelWidth && (Width == File || (TRIDENT_PORTABLE_BUILD &&
                                                                                lane_count(Width) < lane_count(File)));

}  // namespace

template <class Structure, SimdWidth Width, SimdWidth File>
void RenderKernels<Structure, Width, File>::trace_primary_tile(const Structure& structure, const Camera& camera,
                                                               const ImageTile& tile, std::span<Hit> hits,
                                                               PacketVariant variant) {
    static_assert(kDefinedHere<Width, File>);
    using Arch = PacketArchInFile<Width>;
    trace_primary_blocks<Arch, NoCounters>(
        structure, camera, tile, variant,
        [&](const PrimaryBlock<Arch>& block, const HitPacket<Arch>& packet_hits, const NoCounters&) {
            block.store(packet_hits, tile, camera.width(), hits);
        });
}

template <class Structure, SimdWidth Width, SimdWidth File>
void RenderKernels<Structure, Width, File>::count_primary_tile(const Structure& structure, const Camera& camera,
                                                               const ImageTile& tile,
                                                               std::span<TraversalCounters> counts,
                                                               TriangleTest test) requires(Width == File) {
    static_assert(kDefinedHere<Width, File>);
    using Arch = PacketArchInFile<Width>;
    trace_primary_blocks<Arch, TraversalCounters>(
        structure, camera, tile, {.test = test},
        [&](const PrimaryBlock<Arch>& block, const HitPacket<Arch>&, const TraversalCounters& counters) {
            block.for_each_pixel(tile, [&](std::uint32_t x, std::uint32_t y) {
                counts[std::size_t(y) * camera.width() + x] = counters;
            });
        });
}

template <class Structure, SimdWidth Width, SimdWidth File>
bool RenderKernels<Structure, Width, File>::intersect_stream(const Structure& structure, std::span<const Ray> rays,
                                                             std::span<Hit> hits, PacketGrouping grouping,
                                                             PacketVariant variant, std::span<std::uint8_t> alone) {
    static_assert(kDefinedHere<Width, File>);
    using Arch = PacketArchInFile<Width>;
    return trace_stream_packets<kLanes>(structure, rays, grouping, variant, alone, [&](const auto& index) {
        const RayPacket<Arch> packet = gather_packet<Arch>(rays, index);
        HitPacket<Arch> packet_hits(packet);
        NoCounters counters;
        intersect_packet(structure, packet, packet_hits, counters, variant);
        const simd::HitLanes<Arch> lanes(packet_hits);
        for (std::size_t k = 0; k < index.size(); ++k) lanes.store_lane(k, &hits[index[k]]);
    });
}

template <class Structure, SimdWidth Width, SimdWidth File>
bool RenderKernels<Structure, Width, File>::occlude_stream(const Structure& structure, std::span<const Ray> rays,
                                                           std::span<std::uint8_t> occluded, PacketGrouping grouping,
                                                           PacketVariant variant, bool last_occluder,
                                                           std::span<std::uint8_t> alone) {
    static_assert(kDefinedHere<Width, File>);
    using Arch = PacketArchInFile<Width>;
    LastOccluder last;
    LastOccluder* const carried = last_occluder ? &last : nullptr;
    return trace_stream_packets<kLanes>(structure, rays, grouping, variant, alone, [&](const auto& index) {
        NoCounters counters;
        const std::uint32_t bits =
            simd::mask_bits(occlude_packet(structure, gather_packet<Arch>(rays, index), counters, variant, carried));
        for (std::size_t k = 0; k < index.size(); ++k) occluded[index[k]] = (bits >> k) & 1u;
    });
}

template <class Structure, SimdWidth Width, SimdWidth File>
bool RenderKernels<Structure, Width, File>::intersect_array_tile(const Structure& structure, const RayImage& image,
                                                                 const ImageTile& tile, Hit* out,
                                                                 PacketVariant variant) {
    static_assert(kDefinedHere<Width, File>);
    const ArrayTile<PacketArchInFile<Width>> blocks(image, tile);
    return blocks.for_each_block([&](const auto& packet, const auto& block) {
        HitPacket packet_hits(packet);
        NoCounters counters;
        intersect_packet(structure, packet, packet_hits, counters, variant);
        blocks.store(block, simd::HitLanes(packet_hits), out);
        return true;
    });
}

template <class Structure, SimdWidth Width, SimdWidth File>
bool RenderKernels<Structure, Width, File>::occlude_array_tile(const Structure& structure, const RayImage& image,
                                                               const ImageTile& tile, std::uint8_t* out,
                                                               PacketVariant variant) {
    static_assert(kDefinedHere<Width, File>);
    const ArrayTile<PacketArchInFile<Width>> blocks(image, tile);
    LastOccluder last;  // carried from block to block of the tile
    return blocks.for_each_block([&](const auto& packet, const auto& block) {
        NoCounters counters;
        blocks.store(block, simd::mask_bits(occlude_packet(structure, packet, counters, variant, &last)), out);
        return true;
    });
}

// The portable build's 8- and 16-lane files only (single rays; the narrower packets below): the
// 4-lane file's x86-64-v2 is the baseline's own, and a native build's baseline is its kernels'
// instruction set.
#if TRIDENT_PORTABLE_BUILD && TRIDENT_KERNEL_LANES > 4
template <class Structure, SimdWidth File>
[[gnu::flatten]] void SingleRayKernels<Structure, File>::trace_primary_tile(const Structure& structure,
                                                                            const Camera& camera, const ImageTile& tile,
                                                                            std::span<Hit> hits, TriangleTest test,
                                                                            SlabTest slabs) {
    with_traversal_variant(test, slabs, [&](auto test_tag, auto slabs_tag) {
        for (std::uint32_t y = tile.y0; y != tile.y1; ++y)
            for (std::uint32_t x = tile.x0; x != tile.x1; ++x) {
                NoCounters counters;
                hits[std::size_t(y) * camera.width() + x] =
                    structure.template intersect<decltype(test_tag)::value, decltype(slabs_tag)::value>(
                        camera.primary_ray(x, y), counters);
            }
    });
}

template <class Structure, SimdWidth File>
[[gnu::flatten]] void SingleRayKernels<Structure, File>::intersect_rays(const Structure& structure,
                                                                        std::span<const Ray> rays, std::span<Hit> hits,
                                                                        TriangleTest test, SlabTest slabs,
                                                                        RayCoherence coherence) {
    with_traversal_variant(test, slabs, [&](auto test_tag, auto slabs_tag) {
        for (std::size_t i = 0; i < rays.size(); ++i) {
            NoCounters counters;
            hits[i] = is_traced(rays[i]) ? intersect_hinted<decltype(test_tag)::value, decltype(slabs_tag)::value>(
                                               structure, rays[i], counters, coherence)
                                         : Hit{};
        }
    });
}

template <class Structure, SimdWidth File>
[[gnu::flatten]] void SingleRayKernels<Structure, File>::occlude_rays(const Structure& structure,
                                                                      std::span<const Ray> rays,
                                                                      std::span<std::uint8_t> occluded,
                                                                      TriangleTest test, SlabTest slabs,
                                                                      bool last_occluder) {
    with_traversal_variant(test, slabs, [&](auto test_tag, auto slabs_tag) {
        occlude_in_order<decltype(test_tag)::value, decltype(slabs_tag)::value>(structure, rays, occluded,
                                                                                last_occluder);
    });
}

template <class Structure, SimdWidth File>
[[gnu::flatten]] bool SingleRayKernels<Structure, File>::intersect_array_tile(const Structure& structure,
                                                                              const RayImage& image,
                                                                              const ImageTile& tile, Hit* out,
                                                                              TriangleTest test, SlabTest slabs) {
    return trace_array_tile_singly<false>(structure, image, tile, out, test, slabs);
}

template <class Structure, SimdWidth File>
[[gnu::flatten]] bool SingleRayKernels<Structure, File>::occlude_array_tile(const Structure& structure,
                                                                            const RayImage& image,
                                                                            const ImageTile& tile, std::uint8_t* out,
                                                                            TriangleTest test, SlabTest slabs) {
    return trace_array_tile_singly<true>(structure, image, tile, out, test, slabs);
}

template struct SingleRayKernels<BruteForce, kKernelWidth>;
template struct SingleRayKernels<Bvh, kKernelWidth>;
template struct SingleRayKernels<WideBvh<4, 4>, kKernelWidth>;
template struct SingleRayKernels<WideBvh<8, 4>, kKernelWidth>;
template struct SingleRayKernels<WideBvh<16, 4>, kKernelWidth>;
template struct SingleRayKernels<KdTree, kKernelWidth>;
template struct SingleRayKernels<Octree, kKernelWidth>;

#endif

template struct RenderKernels<BruteForce, kKernelWidth>;
template struct RenderKernels<Bvh, kKernelWidth>;
template struct RenderKernels<WideBvh<4, 4>, kKernelWidth>;
template struct RenderKernels<WideBvh<8, 4>, kKernelWidth>;
template struct RenderKernels<WideBvh<16, 4>, kKernelWidth>;
template struct RenderKernels<KdTree, kKernelWidth>;
template struct RenderKernels<Octree, kKernelWidth>;

#if TRIDENT_FILE_HOLDS_W4  // the narrower packets in this file's instruction set (simd/kernel_arch.h)
template struct RenderKernels<BruteForce, SimdWidth::w4, kKernelWidth>;
template struct RenderKernels<Bvh, SimdWidth::w4, kKernelWidth>;
template struct RenderKernels<WideBvh<4, 4>, SimdWidth::w4, kKernelWidth>;
template struct RenderKernels<WideBvh<8, 4>, SimdWidth::w4, kKernelWidth>;
template struct RenderKernels<WideBvh<16, 4>, SimdWidth::w4, kKernelWidth>;
template struct RenderKernels<KdTree, SimdWidth::w4, kKernelWidth>;
template struct RenderKernels<Octree, SimdWidth::w4, kKernelWidth>;
#endif
#if TRIDENT_FILE_HOLDS_W8
template struct RenderKernels<BruteForce, SimdWidth::w8, kKernelWidth>;
template struct RenderKernels<Bvh, SimdWidth::w8, kKernelWidth>;
template struct RenderKernels<WideBvh<4, 4>, SimdWidth::w8, kKernelWidth>;
template struct RenderKernels<WideBvh<8, 4>, SimdWidth::w8, kKernelWidth>;
template struct RenderKernels<WideBvh<16, 4>, SimdWidth::w8, kKernelWidth>;
template struct RenderKernels<KdTree, SimdWidth::w8, kKernelWidth>;
template struct RenderKernels<Octree, SimdWidth::w8, kKernelWidth>;
#endif

}  // namespace trident
