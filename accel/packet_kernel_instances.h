#pragma once
// PacketKernels' members (accel/packet_kernels.h), defined over a structure's packet member
// templates. Included only by the translation unit that instantiates a structure's kernels, after
// the header that defines its packet traversal (which only it and the tests of the traversal's
// parts include):
//     template struct PacketKernels<Bvh, KernelArch>;
// in a file CMake compiles once per packet width (simd/kernel_arch.h), so each kernel is compiled once.
#include <stdexcept>
#include <type_traits>

#include "accel/packet_kernels.h"
#include "core/traversal_variant.h"

namespace trident {
namespace detail {

/// Calls f(test, slabs) as with_traversal_variant() does. Counted traversals (heat maps, the
/// counter tests) only ever use the robust slab test, so they are compiled for it alone: a
/// quarter of each structure's kernels fewer to compile, in both builds the tests make.
template <class Counters, class F>
decltype(auto) with_packet_variant(const PacketVariant& variant, F&& f) {
    if constexpr (std::is_same_v<Counters, NoCounters>) {
        return with_traversal_variant(variant.test, variant.slabs, f);
    } else {
        if (variant.slabs != SlabTest::robust)
            throw std::invalid_argument("packet traversals with counters are compiled for the robust slab test only");
        return with_triangle_test(variant.test, [&](auto test) {
            return f(test, std::integral_constant<SlabTest, SlabTest::robust>{});
        });
    }
}

template <class Structure, class Arch, class Counters>
void intersect_variant(const Structure& structure, const RayPacket<Arch>& rays, HitPacket<Arch>& hits,
                       Counters& counters, PacketVariant variant) {
    with_packet_variant<Counters>(variant, [&](auto test, auto slabs) {
        structure.template intersect<decltype(test)::value, decltype(slabs)::value>(rays, hits, counters,
                                                                                    variant.single_ray_lanes);
    });
}

template <class Structure, class Arch, class Counters>
typename RayPacket<Arch>::Mask occluded_variant(const Structure& structure, const RayPacket<Arch>& rays,
                                                Counters& counters, PacketVariant variant, LastOccluder* last) {
    return with_packet_variant<Counters>(variant, [&](auto test, auto slabs) {
        constexpr TriangleTest kTest = decltype(test)::value;
        constexpr SlabTest kSlabs = decltype(slabs)::value;
        if constexpr (requires { structure.template occluded<kTest, kSlabs>(rays, counters, 0, last); })
            return structure.template occluded<kTest, kSlabs>(rays, counters, variant.single_ray_lanes, last);
        else
            return structure.template occluded<kTest, kSlabs>(rays, counters, variant.single_ray_lanes);
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
                                               TraversalCounters& counters,
                                               PacketVariant variant) requires kOwnWidthArch<Arch> {
    detail::intersect_variant(structure, rays, hits, counters, variant);
}
template <class Structure, class Arch>
auto PacketKernels<Structure, Arch>::occluded(const Structure& structure, const Rays& rays, NoCounters& counters,
                                              PacketVariant variant, LastOccluder* last) -> Mask {
    return detail::occluded_variant(structure, rays, counters, variant, last);
}
template <class Structure, class Arch>
auto PacketKernels<Structure, Arch>::occluded(const Structure& structure, const Rays& rays, TraversalCounters& counters,
                                              PacketVariant variant, LastOccluder* last)
    -> Mask requires kOwnWidthArch<Arch> {
    return detail::occluded_variant(structure, rays, counters, variant, last);
}

}  // namespace trident
