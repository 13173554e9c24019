#pragma once
// The structures' packet traversals as the renderer, the benchmark, the Python module and the tests
// call them: PacketKernels<Structure, Arch>, whose members are defined and instantiated once, in
// the structure's own translation unit (accel/packet_kernel_instances.h), once per packet width
// architecture. Every caller instantiating the traversal kernels again made them the bulk of the
// build: about 300 of the Release build's 742 CPU seconds and 640 of the sanitizer build's 1,377
// (bench/experiments/test_time.md). The same seam is where per-ISA kernels are chosen (issue 34).
//
// The triangle test, the slab test and the single-ray threshold are run-time arguments here and
// compile-time ones inside: one switch per packet, against thousands of cycles of traversal.
#include <cstdint>
#include <type_traits>

#include "accel/accel_stats.h"
#include "core/intersect_triangle.h"
#include "core/slab_test.h"
#include "simd/packet.h"
#include "simd/width.h"

namespace trident {

/// The structure's own threshold for the packet's width: its measured best.
inline constexpr int kDefaultSingleRayLanes = -1;

/// Which packet traversal: the triangle and slab tests, and the subtrees traced ray by ray (those
/// that at most `single_ray_lanes` lanes need; kDefaultSingleRayLanes for the structure's choice,
/// 0 for none). The brute force has no subtrees and ignores it.
struct PacketVariant {
    TriangleTest test = TriangleTest::watertight;
    SlabTest slabs = SlabTest::robust;
    int single_ray_lanes = kDefaultSingleRayLanes;
};

/// What a structure remembers of the occluder that stopped the last shadow ray or packet of a list
/// (the wide BVH: its block of triangles), to test it first for the next, as Haines and Greenberg's
/// shadow cache (1986) tests the last occluder first: neighbouring pixels' shadow rays are mostly
/// stopped by the same few triangles. Only the work depends on it, never an answer; structures
/// without such a test ignore it.
struct LastOccluder {
    static constexpr std::uint32_t kNone = ~std::uint32_t(0);
    std::uint32_t id = kNone;
};

/// Whether `Arch` is a packet width's own architecture (ArchOf), not a narrower width's lanes
/// compiled into a wider kernel file (the portable build's LanesIn, simd/kernel_arch.h).
template <class Arch>
inline constexpr bool kOwnWidthArch =
    std::is_same_v<Arch, ArchOf<SimdWidth::w4>> || std::is_same_v<Arch, ArchOf<SimdWidth::w8>> ||
    std::is_same_v<Arch, ArchOf<SimdWidth::w16>>;

/// Closest hit per live lane into `hits` (constructed from the rays), or the lanes that hit
/// anything: per lane what the structure's single-ray traversal answers (each structure's header
/// says where that holds bit for bit). Counters count per packet; counted traversals take the
/// robust slab test only (std::invalid_argument for the fast one). They exist for a width's own
/// architecture only: heat maps and the counter tests count in the width's own kernel file, so a
/// wider file's copies of the narrower packets (which an explicit instantiation of the struct
/// leaves out, their constraint unmet) would be compiled for nothing.
template <class Structure, class Arch>
struct PacketKernels {
    using Rays = RayPacket<Arch>;
    using Hits = HitPacket<Arch>;
    using Mask = typename Rays::Mask;
    static void intersect(const Structure& structure, const Rays& rays, Hits& hits, NoCounters& counters,
                          PacketVariant variant);
    static void intersect(const Structure& structure, const Rays& rays, Hits& hits, TraversalCounters& counters,
                          PacketVariant variant) requires kOwnWidthArch<Arch>;
    static Mask occluded(const Structure& structure, const Rays& rays, NoCounters& counters, PacketVariant variant,
                         LastOccluder* last = nullptr);
    static Mask occluded(const Structure& structure, const Rays& rays, TraversalCounters& counters,
                         PacketVariant variant, LastOccluder* last = nullptr) requires kOwnWidthArch<Arch>;
};

/// The same with the structure and the architecture deduced.
template <class Structure, class Arch, class Counters>
void intersect_packet(const Structure& structure, const RayPacket<Arch>& rays, HitPacket<Arch>& hits,
                      Counters& counters, PacketVariant variant = {}) {
    PacketKernels<Structure, Arch>::intersect(structure, rays, hits, counters, variant);
}
template <class Structure, class Arch, class Counters>
typename RayPacket<Arch>::Mask occlude_packet(const Structure& structure, const RayPacket<Arch>& rays,
                                              Counters& counters, PacketVariant variant = {},
                                              LastOccluder* last = nullptr) {
    return PacketKernels<Structure, Arch>::occluded(structure, rays, counters, variant, last);
}

}  // namespace trident
