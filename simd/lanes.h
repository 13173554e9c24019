#pragma once
// Lanes<xsimd::batch<float, Arch>>: the packet side of the customization points in core/lanes.h,
// so the slab and triangle tests written over a value type run with one ray per lane. Include
// this before instantiating a core test over a batch.
#include <array>
#include <cstddef>
#include <cstdint>
#include <xsimd/xsimd.hpp>

#include "core/lanes.h"
#include "core/vec3.h"
#include "simd/mask.h"

namespace trident {

template <class Arch>
struct Lanes<xsimd::batch<float, Arch>> {
    using Float = xsimd::batch<float, Arch>;
    using Mask = xsimd::batch_bool<float, Arch>;
    static constexpr std::size_t width = Float::size;
    using Array = std::array<float, width>;

    static Float select(const Mask& mask, const Float& if_true, const Float& if_false) {
        return xsimd::select(mask, if_true, if_false);
    }
    static Float abs(const Float& x) { return xsimd::abs(x); }
    // minps/maxps: b when either is NaN. GCC 12 warns -Wmaybe-uninitialized inside _mm512_min_ps,
    // _mm512_max_ps and _mm512_sqrt_ps (their _mm512_undefined_ps source), so AVX-512 uses the
    // zero-masked forms with every lane kept, which are the same instructions.
    static Float min(const Float& a, const Float& b) {
#if XSIMD_WITH_AVX512F
        if constexpr (simd::kHasMaskRegisters<Arch>) return _mm512_maskz_min_ps(__mmask16(0xFFFF), a, b);
#endif
        return xsimd::min(a, b);
    }
    static Float max(const Float& a, const Float& b) {
#if XSIMD_WITH_AVX512F
        if constexpr (simd::kHasMaskRegisters<Arch>) return _mm512_maskz_max_ps(__mmask16(0xFFFF), a, b);
#endif
        return xsimd::max(a, b);
    }
    static Float sqrt(const Float& x) {
#if XSIMD_WITH_AVX512F
        if constexpr (simd::kHasMaskRegisters<Arch>) return _mm512_maskz_sqrt_ps(__mmask16(0xFFFF), x);
#endif
        return xsimd::sqrt(x);
    }
    static bool any(const Mask& mask) { return xsimd::any(mask); }
    static bool none(const Mask& mask) { return !xsimd::any(mask); }
    static std::uint32_t bits(const Mask& mask) { return simd::mask_bits(mask); }
    static Array to_array(const Float& x) {
        Array lanes;
        x.store_unaligned(lanes.data());
        return lanes;
    }
    static Float from_array(const Array& lanes) { return Float::load_unaligned(lanes.data()); }

    /// Lanes<float>::AxisPermutation lane by lane: the index arithmetic becomes two masks naming
    /// the major axis and one for the swap, and a component is picked with selects. When every
    /// lane permutes alike (`uniform`: neighbouring pixels' rays, unless they straddle a change of
    /// axis or sign), kx, ky, kz are that permutation, as Lanes<float> has them.
    struct AxisPermutation {
        Mask z_from_x, z_from_y, swap_xy;  // z from x, else from y, else from z
        bool uniform = false;
        int kx = 0, ky = 1, kz = 2;

        Vec3T<Float> apply(const Vec3T<Float>& v) const {
            if (uniform) return {v[kx], v[ky], v[kz]};  // whole vectors: no select per lane
            const Float z = xsimd::select(z_from_x, v.x, xsimd::select(z_from_y, v.y, v.z));
            const Float x = xsimd::select(z_from_x, v.y, xsimd::select(z_from_y, v.z, v.x));
            const Float y = xsimd::select(z_from_x, v.z, xsimd::select(z_from_y, v.x, v.y));
            return {xsimd::select(swap_xy, y, x), xsimd::select(swap_xy, x, y), z};
        }
    };
    /// One ray's permutation (Lanes<float>'s) in every lane.
    static AxisPermutation broadcast(const Lanes<float>::AxisPermutation& one) {
        const bool swap_xy = one.kx != (one.kz == 2 ? 0 : one.kz + 1);  // as permutation_to_z numbers them
        return {Mask(one.kz == 0), Mask(one.kz == 1), Mask(swap_xy), true, one.kx, one.ky, one.kz};
    }
    static AxisPermutation major_axis_to_z(const Vec3T<Float>& dir) {
        // largest_abs_axis: |x| >= |y| ? (|x| >= |z| ? x : z) : (|y| >= |z| ? y : z)
        const Float ax = xsimd::abs(dir.x), ay = xsimd::abs(dir.y), az = xsimd::abs(dir.z);
        const Mask x_ge_y = ax >= ay;
        const Mask z_from_x = x_ge_y & (ax >= az);
        const Mask z_from_y = (!x_ge_y) & (ay >= az);
        const Float dir_z = xsimd::select(z_from_x, dir.x, xsimd::select(z_from_y, dir.y, dir.z));
        AxisPermutation out{z_from_x, z_from_y, dir_z < Float(0.0f)};
        static_assert(width < 32);
        constexpr std::uint32_t all = (1u << width) - 1u;
        const std::uint32_t from_x = simd::mask_bits(out.z_from_x), from_y = simd::mask_bits(out.z_from_y),
                            swap = simd::mask_bits(out.swap_xy);
        out.uniform = (from_x == 0 || from_x == all) && (from_y == 0 || from_y == all) && (swap == 0 || swap == all);
        if (out.uniform) {
            const auto shared = Lanes<float>::permutation_to_z(from_x ? 0 : (from_y ? 1 : 2), swap != 0);
            out.kx = shared.kx, out.ky = shared.ky, out.kz = shared.kz;
        }
        return out;
    }
};

}  // namespace trident
