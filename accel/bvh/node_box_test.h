#pragma once
// One ray against one BVH node's box, the x, y and z slabs side by side in three lanes of a
// 4-wide vector: the robust slab formula of core/slab_test.h (detail::clip_to_ordered_slab,
// written over a value type) applied to the three axes at once, then the lanes reduced. About a
// third of the instructions of three scalar slabs, in the loop that dominates traversal. Slabs
// picks the robust or the fast formula (core/slab_test.h).
#include <cstdint>
#include <xsimd/xsimd.hpp>

#include "accel/bvh/bvh_node.h"
#include "core/ray.h"
#include "core/slab_test.h"
#include "simd/lanes.h"

namespace trident::bvh {

template <SlabTest Slabs = SlabTest::robust>
class NodeBoxTest {
    using Float4 = xsimd::make_sized_batch_t<float, 4>;
    using Arch = Float4::arch_type;

public:
    explicit NodeBoxTest(const Ray& ray) {
        const SlabRay slab(ray.origin, ray.dir);
        // The fourth lane computes finite nonsense (origin 0, reciprocal 0) and is never reduced.
        origin_ = Float4{slab.origin.x, slab.origin.y, slab.origin.z, 0.0f};
        inv_dir_ = Float4{slab.inv_dir.x, slab.inv_dir.y, slab.inv_dir.z, 0.0f};
        negative_ = inv_dir_ < Float4(0.0f);
    }

    /// As intersect_slabs: whether [t_min, t_max] meets the node's box, its entry distance in t_entry.
    bool enters(const BvhNode& node, float t_min, float t_max, float& t_entry) const {
        Float4 entry(t_min), exit(t_max);
        const Float4 lo = load_xyz(&node.bounds.lo.x), hi = load_xyz(&node.bounds.hi.x);
        if constexpr (Slabs == SlabTest::robust) {
            // The planes ordered by the ray's signs once per node (two selects on a mask fixed per
            // ray) rather than the robust formula's compares and selects per plane.
            detail::clip_to_ordered_slab(xsimd::select(negative_, hi, lo), xsimd::select(negative_, lo, hi), origin_,
                                         inv_dir_, entry, exit);
        } else {
            detail::clip_to_slab<Slabs>(lo, hi, origin_, inv_dir_, entry, exit);
        }
        t_entry = largest_of_xyz(entry);
        return t_entry <= smallest_of_xyz(exit);
    }

private:
    /// x, y, z from memory and a zero: the fourth float read is the next field of the node
    /// (bounds.hi.x after lo, the index after hi).
    static Float4 load_xyz(const float* xyz) {
        const Float4 keep_xyz = xsimd::bitwise_cast<Float4>(xsimd::batch<std::int32_t, Arch>{-1, -1, -1, 0});
        return Float4::load_unaligned(xyz) & keep_xyz;
    }
    template <std::uint32_t A, std::uint32_t B, std::uint32_t C>
    static Float4 lanes(const Float4& v) {
        return xsimd::swizzle(v, xsimd::batch_constant<xsimd::batch<std::uint32_t, Arch>, A, B, C, 3>());
    }
    static float largest_of_xyz(const Float4& v) {
        return Lanes<Float4>::max(v, Lanes<Float4>::max(lanes<1, 2, 0>(v), lanes<2, 0, 1>(v))).get(0);
    }
    static float smallest_of_xyz(const Float4& v) {
        return Lanes<Float4>::min(v, Lanes<Float4>::min(lanes<1, 2, 0>(v), lanes<2, 0, 1>(v))).get(0);
    }

    Float4 origin_, inv_dir_;
    xsimd::batch_bool<float, Arch> negative_;  // per axis: 1 / dir < 0 (dir -0 included)
};

}  // namespace trident::bvh
