#pragma once
// The renderer's packet loops, one width at a time: primary rays of an image tile made and traced
// as packets, a tile's traversal counts, and up to a packet's worth of listed rays. Declared here
// with no batch in sight and defined in render_kernels.cpp, which CMake compiles once per packet
// width with that width's instruction set (simd/kernel_arch.h), so the files that pick a width at
// run time (trace.cpp, heat_map.cpp, ray_stream.cpp) compile for the build's baseline.
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>

#include "accel/accel_stats.h"
#include "accel/packet_kernels.h"
#include "camera/camera.h"
#include "core/intersect_triangle.h"
#include "core/ray.h"
#include "core/ray_coherence.h"
#include "core/slab_test.h"
#include "core/traversal_variant.h"
#include "render/image_tiles.h"
#include "render/ray_arrays.h"
#include "render/stream_packets.h"
#include "simd/width.h"

namespace trident {

/// A structure whose packets may walk every lane alone from the root (the wide BVH's incoherent
/// packets over a large tree): it says so of a packet of listed rays before the packet is built,
/// and of every incoherent packet at once (accel/bvh/wide_bvh.h).
template <class Structure>
concept WalksLanesAlone = requires(const Structure& structure, std::span<const Ray> rays,
                                   std::span<const std::size_t> index) {
    { structure.packet_walks_lanes_alone(rays, index) } -> std::same_as<bool>;
    { structure.incoherent_packets_walk_alone() } -> std::same_as<bool>;
};

/// `Width`'s packet loops as compiled in the kernel file of width `File`: the width's own file, or
/// in the portable build a wider one (simd/kernel_arch.h, LanesIn): 4-lane packets in the 8- or
/// 16-lane file, whose instruction set the 4-lane file, being the baseline's, lacks, and 8-lane
/// packets in the 16-lane file (EVEX encodings, 32 registers).
template <class Structure, SimdWidth Width, SimdWidth File = Width>
struct RenderKernels {
    static constexpr std::size_t kLanes = lane_count(Width);

    /// The closest hits of the tile's primary rays into `hits` (the image's, row-major).
    static void trace_primary_tile(const Structure& structure, const Camera& camera, const ImageTile& tile,
                                   std::span<Hit> hits, PacketVariant variant);
    /// Each of the tile's pixels gets its packet's counters (the robust slab test). In the width's
    /// own file only, where its counted packet traversals are (PacketKernels).
    static void count_primary_tile(const Structure& structure, const Camera& camera, const ImageTile& tile,
                                   std::span<TraversalCounters> counts, TriangleTest test) requires(Width == File);
    /// A list of rays cut into packets as `grouping` says (for_each_stream_packet), each gathered,
    /// walked and its results written to out[i]: the closest hits, or the occluded rays as 1, the
    /// shadow packets carrying the last occluder from packet to packet when `last_occluder` is set
    /// (LastOccluder). The whole loop is here, not only the walk, so that in the portable build the
    /// gathers and scatters get the kernel file's instruction set too (the baseline's copy of the
    /// loop cost Teapot's 16-lane shadow packets 4% against the native build, perf). Untraced rays'
    /// results are not written. A packet whose lanes would all walk alone from the root (the wide
    /// BVH's incoherent packets over a large tree, packet_walks_lanes_alone) is not built: its rays
    /// get alone[i] = 1, for the caller to trace as single rays. Returns whether any did.
    static bool intersect_stream(const Structure& structure, std::span<const Ray> rays, std::span<Hit> hits,
                                 PacketGrouping grouping, PacketVariant variant, std::span<std::uint8_t> alone);
    static bool occlude_stream(const Structure& structure, std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                               PacketGrouping grouping, PacketVariant variant, bool last_occluder,
                               std::span<std::uint8_t> alone);
    /// The tile's rays of an image of rays in arrays, packet block by packet block: the closest
    /// hits, or the occluded rays as 1, written to out[image.index(x, y)]. False, some of the
    /// tile's results written, at the first packet holding a ray that cannot be traced.
    static bool intersect_array_tile(const Structure& structure, const RayImage& image, const ImageTile& tile,
                                     Hit* out, PacketVariant variant);
    static bool occlude_array_tile(const Structure& structure, const RayImage& image, const ImageTile& tile,
                                   std::uint8_t* out, PacketVariant variant);
};

/// Single rays compiled in the kernel file of `File`'s width, so with its instruction set: in the
/// portable build the wide BVH's node tests, the triangle tests and everything else a ray's walk
/// inlines get AVX2 or AVX-512 code on a CPU that has it, where the baseline's copy is SSE4.2
/// (only the 8- and 16-lane files hold them, the 4-lane one being the baseline's x86-64-v2).
/// Each walk is inlined into these loops (gnu::flatten), so it is compiled here and not taken
/// from the baseline's COMDAT copy; the hits are those of the baseline's walk, bit for bit.
template <class Structure, SimdWidth File>
struct SingleRayKernels {
    /// The closest hits of the tile's primary rays into `hits` (the image's, row-major).
    static void trace_primary_tile(const Structure& structure, const Camera& camera, const ImageTile& tile,
                                   std::span<Hit> hits, TriangleTest test, SlabTest slabs);
    /// One result per ray (untraceable rays get none: a miss, not occluded).
    static void intersect_rays(const Structure& structure, std::span<const Ray> rays, std::span<Hit> hits,
                               TriangleTest test, SlabTest slabs, RayCoherence coherence);
    static void occlude_rays(const Structure& structure, std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                             TriangleTest test, SlabTest slabs, bool last_occluder);
    /// RenderKernels' array tiles, one ray at a time (trace_tile_singly).
    static bool intersect_array_tile(const Structure& structure, const RayImage& image, const ImageTile& tile,
                                     Hit* out, TriangleTest test, SlabTest slabs);
    static bool occlude_array_tile(const Structure& structure, const RayImage& image, const ImageTile& tile,
                                   std::uint8_t* out, TriangleTest test, SlabTest slabs);
};

/// The tile's rays of an image of rays in arrays one at a time (trace_tile_singly), each through
/// the structure's single-ray walk with `test` and `slabs`: the closest hits, or the occluded rays
/// as 1 (AnyHit), any hit with the last occluder tried first where the structure can
/// (LastOccluder). For SingleRayKernels' kernel files and the baseline's own single rays alike.
template <bool AnyHit, class Structure, class Result>
bool trace_array_tile_singly(const Structure& structure, const RayImage& image, const ImageTile& tile, Result* out,
                             TriangleTest test, SlabTest slabs) {
    return with_traversal_variant(test, slabs, [&](auto test_tag, auto slabs_tag) {
        constexpr TriangleTest kTest = decltype(test_tag)::value;
        constexpr SlabTest kSlabs = decltype(slabs_tag)::value;
        [[maybe_unused]] LastOccluder last;
        return trace_tile_singly(image, tile, out, [&](const Ray& ray) {
            NoCounters counters;
            if constexpr (!AnyHit)
                return structure.template intersect<kTest, kSlabs>(ray, counters);
            else if constexpr (requires { structure.template occluded<kTest, kSlabs>(ray, counters, last); })
                return std::uint8_t(structure.template occluded<kTest, kSlabs>(ray, counters, last));
            else
                return std::uint8_t(structure.template occluded<kTest, kSlabs>(ray, counters));
        });
    });
}

/// In the portable build (TRIDENT_PORTABLE_BUILD), calls f.template operator()<File>() for the
/// widest kernel file the CPU and the cap allow, when it holds more than `Lanes` lanes, and
/// returns true: the caller then runs its work of `Lanes` lanes or fewer there. Returns false,
/// calling nothing, otherwise and in a native build, whose every file has its kernels' own
/// instruction set.
template <std::size_t Lanes, class F>
bool in_kernel_file_wider_than(F&& f) {
#if TRIDENT_PORTABLE_BUILD
    const SimdWidth file = widest_supported();
    if (lane_count(file) <= Lanes) return false;
    dispatch_width(file, [&]<SimdWidth File>() {
        if constexpr (lane_count(File) > Lanes) f.template operator()<File>();
    });
    return true;
#else
    (void)f;
    return false;
#endif
}

/// The single rays' form of it: f.template operator()<File>() for an 8- or 16-lane file, where
/// the caller traces its single rays (SingleRayKernels<Structure, File>) instead of at the
/// baseline, whose 4-lane instruction set they would otherwise have.
template <class F>
bool in_widest_kernel_file(F&& f) {
    return in_kernel_file_wider_than<lane_count(SimdWidth::w4)>(std::forward<F>(f));
}

/// Calls f.template operator()<W, File>() for the packets of `width` (not scalar): W == width, and
/// File the kernel file they run in, the widest the CPU and the cap allow in the portable build
/// (RenderKernels<Structure, W, File>), W's own in a native one. Throws as dispatch_width() when
/// the width is not runnable here.
template <class F>
void dispatch_packet_width(SimdWidth width, F&& f) {
    dispatch_width(width, [&]<SimdWidth W>() {
        if constexpr (W != SimdWidth::scalar) {
            const bool wider = in_kernel_file_wider_than<lane_count(W)>(
                [&]<SimdWidth File>() { f.template operator()<W, File>(); });
            if (!wider) f.template operator()<W, W>();
        }
    });
}

}  // namespace trident
