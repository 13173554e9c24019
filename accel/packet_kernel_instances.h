#pragma once
// PacketKernels' members (accel/packet_kernels.h), defined over a structure's packet member
// templates. Included only by the translation unit that instantiates a structure's kernels, after
// the header that defines its packet traversal, which no other file includes:
//     template struct PacketKernels<Bvh, xsimd::avx2>;
// once per architecture compiled in (XSIMD_WITH_...), so each kernel is compiled once.
#include "accel/packet_kernels.h"
#include "core/traversal_variant.h"

namespace trident {
namespace detail {

template <class Structure, class Arch, class Counters>
void intersect_variant(const Structure& structure, const RayPacket<Arch>& rays, HitPacket<Arch>& hits,
                       Counters& counters, PacketVariant variant) {
    with_traversal_variant(variant.test, variant.slabs, [&](auto test, auto slabs) {
        structure.template intersect<decltype(test)::value, decltype(slabs)::value>(rays, hits, counters,
                                                                                    variant.single_ray_lanes);
    });
}

template <class Structure, class Arch, class Counters>
typename RayPacket<Arch>::Mask occluded_variant(const Structure& structure, const RayPacket<Arch>& rays,
                                                Counters& counters, PacketVariant variant) {
    return with_traversal_variant(variant.test, variant.slabs, [&](auto test, auto slabs) {
        return structure.template occluded<decltype(test)::value, decltype(slabs)::value>(rays, counters,
                                                                                          variant.single_ray_lanes);
    });
}

}  // namespace detail

template <class Structure, class Arch>
void PacketKernels<Structure, Arch>::intersect(const Structure& structure, const Rays& rays, Hits& hits,
                                               NoCounters& counters, PacketVariant variant) {
    detail::intersect_variant(structure, rays, hits, counters, variant);
}
template <class Structure, class Arch>
void PacketKernels<Structure, Arch>::intersect(const Structure& structure, const Rays& rays, Hits& hits,
                                               TraversalCounters& counters, PacketVariant variant) {
    detail::intersect_variant(structure, rays, hits, counters, variant);
}
template <class Structure, class Arch>
auto PacketKernels<Structure, Arch>::occluded(const Structure& structure, const Rays& rays, NoCounters& counters,
                                              PacketVariant variant) -> Mask {
    return detail::occluded_variant(structure, rays, counters, variant);
}
template <class Structure, class Arch>
auto PacketKernels<Structure, Arch>::occluded(const Structure& structure, const Rays& rays, TraversalCounters& counters,
                                              PacketVariant variant) -> Mask {
    return detail::occluded_variant(structure, rays, counters, variant);
}

}  // namespace trident
