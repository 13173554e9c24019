#pragma once
// One test of all Width child boxes of a wide node against a whole group of rays that share an
// octant (Reshetov, Soupikov and Hurley 2005, "Multi-level ray tracing algorithm"; Embree's
// frustum.h and node_intersector_frustum.h): per axis, the interval of the rays' origins and of
// their reciprocal directions, so that each slab distance of every ray lies within an interval
// computed once for the group. A child none of the rays can enter is dropped before any lane is
// tested against it.
//
// The bounds are conservative against the lanes' own rounded arithmetic, not only against exact
// arithmetic: a lane's near distance is fl(fl(plane - origin) * inv_dir), and rounding preserves
// order, so the smallest of the corner products fl(fl(plane - origin bound) * inv_dir bound) is at
// most every lane's value (with inv_dir of one sign, two corners suffice: the constructor says
// which); likewise the largest for far distances, widened as the robust test widens them. Dropping a child is then a decision every lane's own test would have made.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <xsimd/xsimd.hpp>

#include "accel/bvh/wide_box_test.h"
#include "accel/bvh/wide_node.h"
#include "core/slab_test.h"
#include "simd/lanes.h"
#include "simd/mask.h"
#include "simd/packet.h"

namespace trident::bvh {

/// Per axis the rays' extremes: origins in [origin_lo, origin_hi], reciprocal directions in
/// [inv_lo, inv_hi], all of one sign and finite.
struct RayGroupBounds {
    float origin_lo[3], origin_hi[3], inv_lo[3], inv_hi[3];
    bool negative[3];
    float tmin_lo;

    /// Whether the rays leave from one point (a pinhole camera's): then the bounds are a tight
    /// frustum, where rays from spread origins (shadow rays) give a loose one.
    bool shares_origin() const {
        return origin_lo[0] == origin_hi[0] && origin_lo[1] == origin_hi[1] && origin_lo[2] == origin_hi[2];
    }

    /// The bounds of a packet's live lanes, or nothing when they do not share an octant or some
    /// direction component is zero (its reciprocal infinite), where the intervals say nothing.
    /// Every return names `out`, so it is built in the caller's object: filled field by field and
    /// then copied whole, the copy's wide loads waited for the narrow stores to retire (no store
    /// forwarding), and that stall was several percent of a primary packet's walk on Teapot (perf).
    template <class Arch>
    static std::optional<RayGroupBounds> of(const RayPacket<Arch>& rays, const typename RayPacket<Arch>::Mask& live) {
        using Float = typename RayPacket<Arch>::Float;
        std::optional<RayGroupBounds> out;
        if (!rays.shares_octant()) return out;
        RayGroupBounds& bounds = out.emplace();
        const Float inf(kInfinity);
        // Each horizontal min is a chain of shuffles, and a packet's set-up took ten of them where
        // it took sixteen: the largest |1 / dir| is the larger of -inv_lo and inv_hi, and where
        // the live lanes share an origin (a camera's packets) its one compare finds the upper
        // bound equal to the lower one.
        for (int axis = 0; axis < 3; ++axis) {
            const Float inv = rays.slab.inv_dir[axis], origin = rays.slab.origin[axis];
            bounds.inv_lo[axis] = simd::horizontal_min(xsimd::select(live, inv, inf));
            bounds.inv_hi[axis] = -simd::horizontal_min(xsimd::select(live, -inv, inf));
            if (!(std::max(-bounds.inv_lo[axis], bounds.inv_hi[axis]) < kInfinity)) {
                out.reset();
                return out;
            }
            const float origin_lo = simd::horizontal_min(xsimd::select(live, origin, inf));
            bounds.origin_lo[axis] = origin_lo;
            bounds.origin_hi[axis] = xsimd::any(live & (origin != Float(origin_lo)))
                                         ? -simd::horizontal_min(xsimd::select(live, -origin, inf))
                                         : origin_lo;
            bounds.negative[axis] = (rays.octant >> axis & 1) != 0;
        }
        bounds.tmin_lo = simd::horizontal_min(xsimd::select(live, rays.tmin, inf));
        return out;
    }
};

/// Chunk in the name, as for WideBoxTest (wide_box_test.h says why).
template <std::size_t Width, SlabTest Slabs, std::size_t Chunk = kNodeChunk<Width>>
class WideFrustumTest {
public:
    using Float = xsimd::make_sized_batch_t<float, Chunk>;  // a whole node, or halves of it
    static constexpr std::size_t kChunk = Chunk;

    explicit WideFrustumTest(const RayGroupBounds& group) : tmin_lo_(group.tmin_lo) {
        for (int axis = 0; axis < 3; ++axis) {
            // The product (plane - origin) * inv_dir grows with the plane's offset where inv_dir is
            // positive and shrinks where it is negative, so the smallest near distance takes the
            // smallest offset (the farthest origin) there and the largest one here, and the
            // largest far distance the other way round; only inv_dir's two ends remain to try.
            near_origin_[axis] = Float(group.negative[axis] ? group.origin_lo[axis] : group.origin_hi[axis]);
            far_origin_[axis] = Float(group.negative[axis] ? group.origin_hi[axis] : group.origin_lo[axis]);
            inv_lo_[axis] = Float(group.inv_lo[axis]);
            inv_hi_[axis] = Float(group.inv_hi[axis]);
            near_row_[axis] = near_row(axis, group.negative[axis]);
            far_row_[axis] = far_row(axis, group.negative[axis]);
        }
    }

    /// Bit k set when some ray of the group, limited to t <= t_max_hi, may enter child k's box;
    /// clear only where none can. entry_lo[k]: at most any ray's entry distance into child k.
    std::uint32_t may_enter(const WideNode<Width>& node, float t_max_hi, std::array<float, Width>& entry_lo) const {
        using L = Lanes<Float>;
        std::uint32_t may = 0;
        for (std::size_t first = 0; first < Width; first += kChunk) {
            Float entry(tmin_lo_), exit(t_max_hi);
            for (int axis = 0; axis < 3; ++axis) {
                const Float near = Float::load_aligned(node.bounds[near_row_[axis]] + first);
                const Float far = Float::load_aligned(node.bounds[far_row_[axis]] + first);
                const Float near_offset = near - near_origin_[axis], far_offset = far - far_origin_[axis];
                const Float smallest_near = L::min(near_offset * inv_lo_[axis], near_offset * inv_hi_[axis]);
                Float largest_far = L::max(far_offset * inv_lo_[axis], far_offset * inv_hi_[axis]);
                if constexpr (Slabs == SlabTest::robust) largest_far = largest_far * Float(detail::kFarScale);
                entry = L::max(smallest_near, entry);
                exit = L::min(largest_far, exit);
            }
            entry.store_unaligned(entry_lo.data() + first);
            may |= simd::mask_bits(entry <= exit) << first;
        }
        return may;
    }

private:
    Float near_origin_[3], far_origin_[3], inv_lo_[3], inv_hi_[3];
    int near_row_[3], far_row_[3];
    float tmin_lo_;
};

}  // namespace trident::bvh
