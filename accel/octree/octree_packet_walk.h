#pragma once
// The parametric walk of octree_walk.h for every lane of a ray packet at once. Each lane computes
// the values the single-ray walk computes for its ray, with the same operations (so the same bits):
// the root slabs and the centre-plane parameters; a child's slabs come from child_slabs(), which
// serves both. Only the mirror is the packet's: the lanes of one octant group (octree_packet.h)
// share it, so the packet can take the children in one order that is front to back for all.
//
// A lane parallel to an axis is not mirrored on it by the single-ray walk; in a group mirrored on
// that axis its centre-plane parameter changes sign instead (+inf <-> -inf), which flips the
// mirrored child bit with the mirror and leaves the real children, and every slab value, as they
// were.
#include <array>
#include <bit>
#include <cstdint>
#include <xsimd/xsimd.hpp>

#include "accel/octree/octree_node.h"
#include "accel/octree/octree_walk.h"
#include "simd/lanes.h"
#include "simd/packet.h"

namespace trident {

/// enter_root() for every lane: the root slabs along the whole line of each ray, mirrored on the
/// axes where the lane's direction is negative.
template <class Arch>
struct PacketRootEntry {
    using Float = xsimd::batch<float, Arch>;
    using Mask = xsimd::batch_bool<float, Arch>;

    NodeSlabsT<Float> slabs;
    Vec3T<Mask> parallel;  // the lane never crosses a plane of this axis (walk.parallel)
    Vec3T<Mask> negative;  // the lane crosses the planes of this axis going down (walk.mirror)
    Mask entered;          // enter_root() returned true

    PacketRootEntry(const RayPacket<Arch>& rays, const OctreeCube& cube) {
        const Float infinity(kInfinity);
        Mask outside(false);
        for (int axis = 0; axis < 3; ++axis) {
            const float lo = cube.lo[axis], hi = cube.lo[axis] + cube.size;
            const Float o = rays.origin[axis], d = rays.dir[axis];
            const Float inv = rays.slab.inv_dir[axis];  // 1 / d, as enter_root() computes it
            const Mask down = d < Float(0.0f);          // -0 goes up, as in enter_root()
            const Float t_lo = (xsimd::select(down, Float(hi), Float(lo)) - o) * inv;
            const Float t_hi = (xsimd::select(down, Float(lo), Float(hi)) - o) * inv;
            const Mask finite = (xsimd::abs(t_lo) < infinity) & (xsimd::abs(t_hi) < infinity);
            slabs.t0[axis] = xsimd::select(finite, t_lo, -infinity);
            slabs.t1[axis] = xsimd::select(finite, t_hi, infinity);
            parallel[axis] = !finite;
            negative[axis] = finite & down;
            outside = outside | ((!finite) & ((o < Float(lo)) | (o > Float(hi))));
        }
        entered = (!outside) & !(parallel.x & parallel.y & parallel.z);
    }
};

/// slab_midpoints() for every lane, in a group mirrored by `mirror` (bit i: axis i).
template <class Arch>
Vec3T<xsimd::batch<float, Arch>> packet_slab_midpoints(const RayPacket<Arch>& rays, const PacketRootEntry<Arch>& root,
                                                       unsigned mirror,
                                                       const NodeSlabsT<xsimd::batch<float, Arch>>& slabs,
                                                       const OctreeCube& cell) {
    using Float = xsimd::batch<float, Arch>;
    const Vec3f mid = cell.mid();
    const auto midpoint = [&](int axis) {
        const Float crossing = Float(0.5f) * (slabs.t0[axis] + slabs.t1[axis]);
        // Below the centre plane the single-ray walk takes +inf (the lower child, never left).
        const float below = (mirror >> axis) & 1u ? -kInfinity : kInfinity;
        const Float beside = xsimd::select(rays.origin[axis] < Float(mid[axis]), Float(below), Float(-below));
        return xsimd::select(root.parallel[axis], beside, crossing);
    };
    return {midpoint(0), midpoint(1), midpoint(2)};  // not zeroed first (child_slabs() says why)
}

/// The stored children of a node with child mask `mask`, in mirrored numbering: bit c set when
/// child c ^ mirror is stored (mirroring an axis swaps the halves along it).
inline unsigned mirrored_child_mask(unsigned mask, unsigned mirror) {
    if (mirror & 1u) mask = ((mask & 0x55u) << 1) | ((mask & 0xAAu) >> 1);
    if (mirror & 2u) mask = ((mask & 0x33u) << 2) | ((mask & 0xCCu) >> 2);
    if (mirror & 4u) mask = ((mask & 0x0Fu) << 4) | ((mask & 0xF0u) >> 4);
    return mask;
}

/// Of the lanes in `touching`, whose line only touches child `child` (mirrored numbering) of a node
/// with slabs `slabs` and midpoints `tm`, those whose single-ray walk enters it (walk_enters()).
/// Rare (lines through a cell edge or corner), so done lane by lane with the single-ray code.
template <class Arch>
xsimd::batch_bool<float, Arch> lanes_entering_touched(const xsimd::batch_bool<float, Arch>& touching, unsigned child,
                                                      const NodeSlabsT<xsimd::batch<float, Arch>>& slabs,
                                                      const Vec3T<xsimd::batch<float, Arch>>& tm) {
    using L = Lanes<xsimd::batch<float, Arch>>;
    const auto t0x = L::to_array(slabs.t0.x), t0y = L::to_array(slabs.t0.y), t0z = L::to_array(slabs.t0.z);
    const auto t1x = L::to_array(slabs.t1.x), t1y = L::to_array(slabs.t1.y), t1z = L::to_array(slabs.t1.z);
    const auto tmx = L::to_array(tm.x), tmy = L::to_array(tm.y), tmz = L::to_array(tm.z);
    std::array<bool, L::width> entering{};
    for (std::uint32_t bits = simd::mask_bits(touching); bits != 0; bits &= bits - 1) {
        const int i = std::countr_zero(bits);
        const NodeSlabs lane{{t0x[i], t0y[i], t0z[i]}, {t1x[i], t1y[i], t1z[i]}};
        entering[i] = walk_enters(child, lane, {tmx[i], tmy[i], tmz[i]});
    }
    return xsimd::batch_bool<float, Arch>::load_unaligned(entering.data());
}

}  // namespace trident
