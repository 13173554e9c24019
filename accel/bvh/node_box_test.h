#pragma once
// One ray against one BVH node's box, the x, y and z slabs side by side in three lanes of a
// 4-wide vector: the robust slab formula of core/slab_test.h (detail::clip_to_ordered_slab,
// written over a value type) applied to the three axes at once, then the lanes reduced. About a
// third of the instructions of three scalar slabs, in the loop that dominates traversal. Slabs
// picks the robust or the fast formula (core/slab_test.h). enters_pair tests a node's two
// children at once in the two halves of an 8-wide vector where the file has AVX; the portable
// build's SSE4.2 baseline tests them one after the other, with the same bits.
#include <immintrin.h>

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
#if XSIMD_WITH_AVX2
        origin8_ = pair(origin_, origin_);
        inv_dir8_ = pair(inv_dir_, inv_dir_);
        negative8_ = inv_dir8_ < Float8(0.0f);
#endif
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

    /// enters() for two nodes at once, the first box in the low four lanes of an 8-wide vector
    /// and the second in the high four: the same operations on each lane as enters(), so the
    /// same results bit for bit, for one vector instruction where enters() twice takes two.
    /// Returns a bit per node entered (1: first, 2: second).
    unsigned enters_pair(const BvhNode& first, const BvhNode& second, float t_min, float t_max, float& t_first,
                         float& t_second) const {
#if !XSIMD_WITH_AVX2
        return unsigned(enters(first, t_min, t_max, t_first)) | unsigned(enters(second, t_min, t_max, t_second)) << 1;
#else
        const Float8 lo = pair(load_xyz(&first.bounds.lo.x), load_xyz(&second.bounds.lo.x));
        const Float8 hi = pair(load_xyz(&first.bounds.hi.x), load_xyz(&second.bounds.hi.x));
        Float8 entry(t_min), exit(t_max);
        if constexpr (Slabs == SlabTest::robust)
            detail::clip_to_ordered_slab(xsimd::select(negative8_, hi, lo), xsimd::select(negative8_, lo, hi), origin8_,
                                         inv_dir8_, entry, exit);
        else
            detail::clip_to_slab<Slabs>(lo, hi, origin8_, inv_dir8_, entry, exit);
        // Within each half, the largest entry and smallest exit of lanes x, y, z, in lane x.
        const __m256 e = entry, x = exit;
        const __m256 largest = _mm256_max_ps(e, _mm256_max_ps(_mm256_permute_ps(e, kYzx), _mm256_permute_ps(e, kZxy)));
        const __m256 smallest = _mm256_min_ps(x, _mm256_min_ps(_mm256_permute_ps(x, kYzx), _mm256_permute_ps(x, kZxy)));
        t_first = _mm256_cvtss_f32(largest);
        t_second = _mm_cvtss_f32(_mm256_extractf128_ps(largest, 1));
        const unsigned inside = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(largest, smallest, _CMP_LE_OQ)));
        return (inside & 1u) | (inside >> 3 & 2u);
#endif
    }

private:
#if XSIMD_WITH_AVX2
    using Float8 = xsimd::batch<float, xsimd::avx2>;
    // _mm256_permute_ps orders: lanes (y, z, x, w) and (z, x, y, w) of each half.
    static constexpr int kYzx = 1 | 2 << 2 | 0 << 4 | 3 << 6, kZxy = 2 | 0 << 2 | 1 << 4 | 3 << 6;
    static Float8 pair(const Float4& low, const Float4& high) { return Float8(_mm256_set_m128(high, low)); }
#endif

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
#if XSIMD_WITH_AVX2
    Float8 origin8_, inv_dir8_;                // the same, twice, for enters_pair
    xsimd::batch_bool<float, xsimd::avx2> negative8_;
#endif
};

}  // namespace trident::bvh
