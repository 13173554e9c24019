#pragma once
// Lane-mask helpers xsimd 8.1 lacks: a mask as bits and back, the count and first of its set lanes, a
// select of 32-bit integers (triangle ids) by a float mask, and a horizontal min.
// Each width has its own mask representation: a vector of all-ones/all-zeros lanes up to AVX2,
// a k-register (one bit a lane) from AVX-512 on.
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <xsimd/xsimd.hpp>

namespace trident::simd {

template <class Arch>
inline constexpr bool kHasMaskRegisters = std::is_base_of_v<xsimd::avx512f, Arch>;
template <class Arch>
inline constexpr bool kIs256Bit = std::is_base_of_v<xsimd::avx, Arch>;
template <class Arch>
inline constexpr bool kIs128Bit = std::is_base_of_v<xsimd::sse2, Arch>;

/// Bit i set when lane i is set.
template <class Arch>
std::uint32_t mask_bits(const xsimd::batch_bool<float, Arch>& mask) {
    if constexpr (kHasMaskRegisters<Arch>) {
        return mask.data;
    } else if constexpr (kIs256Bit<Arch>) {
        return static_cast<std::uint32_t>(_mm256_movemask_ps(mask));
    } else {
        static_assert(kIs128Bit<Arch>, "no mask helpers for this architecture");
        return static_cast<std::uint32_t>(_mm_movemask_ps(mask));
    }
}

/// The mask whose lane i is set when bit i of `bits` is: mask_bits' inverse, for masks kept as
/// bits (four bytes where a vector mask of 8 lanes takes 32).
template <class Arch>
xsimd::batch_bool<float, Arch> mask_from_bits(std::uint32_t bits) {
    using Mask = xsimd::batch_bool<float, Arch>;
    if constexpr (kHasMaskRegisters<Arch>) {
        return Mask(static_cast<typename Mask::register_type>(bits));
    } else {
        // Each lane's own bit, compared: registers spelled through Arch, as select_index says.
        using Ids = xsimd::batch<std::uint32_t, Arch>;
        using IdRegister = typename Ids::register_type;
        alignas(32) static constexpr std::array<std::uint32_t, Mask::size> kLaneBit = [] {
            std::array<std::uint32_t, Mask::size> out{};
            for (std::size_t i = 0; i < Mask::size; ++i) out[i] = 1u << i;
            return out;
        }();
        const IdRegister lane_bit = Ids::load_aligned(kLaneBit.data()), all = Ids(bits);
        if constexpr (kIs256Bit<Arch>) {
            static_assert(std::is_base_of_v<xsimd::avx2, Arch>, "256-bit integer compares need AVX2");
            return Mask(_mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(all, lane_bit), lane_bit)));
        } else {
            static_assert(kIs128Bit<Arch>, "no mask helpers for this architecture");
            return Mask(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(all, lane_bit), lane_bit)));
        }
    }
}

template <class Arch>
int active_lane_count(const xsimd::batch_bool<float, Arch>& mask) {
    return std::popcount(mask_bits(mask));
}

/// Index of the lowest set lane; the width when no lane is set.
template <class Arch>
int first_active_lane(const xsimd::batch_bool<float, Arch>& mask) {
    const std::uint32_t bits = mask_bits(mask);
    return bits == 0 ? int(xsimd::batch_bool<float, Arch>::size) : std::countr_zero(bits);
}

/// Per lane, if_true where the float mask is set, else if_false, over uint32 lanes (triangle ids).
/// Written with intrinsics: xsimd 8.1's integer select for AVX-512BW does not compile at -O0.
template <class Arch>
xsimd::batch<std::uint32_t, Arch> select_index(const xsimd::batch_bool<float, Arch>& mask,
                                               const xsimd::batch<std::uint32_t, Arch>& if_true,
                                               const xsimd::batch<std::uint32_t, Arch>& if_false) {
    using Register = typename xsimd::batch<std::uint32_t, Arch>::register_type;
    const Register t = if_true, f = if_false;
    if constexpr (kHasMaskRegisters<Arch>) {
        return _mm512_mask_blend_epi32(mask.data, f, t);
    } else if constexpr (kIs256Bit<Arch>) {
        return _mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(f), _mm256_castsi256_ps(t), mask));
    } else {
        static_assert(kIs128Bit<Arch>, "no mask helpers for this architecture");
        return _mm_castps_si128(_mm_blendv_ps(_mm_castsi128_ps(f), _mm_castsi128_ps(t), mask));
    }
}

/// Lane i holding i (as a float, exact), for masks of lanes made in registers: compared with a
/// broadcast count, the first lanes; with a broadcast index, one lane. A mask or vector loaded from
/// an array written lane by lane waits until those narrow stores retire (no store forwarding).
template <class Arch>
xsimd::batch<float, Arch> lane_indices() {
    using Float = xsimd::batch<float, Arch>;
    alignas(64) static constexpr std::array<float, Float::size> kIndex = [] {
        std::array<float, Float::size> out{};
        for (std::size_t i = 0; i < Float::size; ++i) out[i] = float(i);
        return out;
    }();
    return Float::load_aligned(kIndex.data());
}

/// Smallest lane; NaN lanes are skipped (+inf when every lane is NaN). For the smallest active
/// lane, pass select(active, x, +inf). A tree of halving shuffles: the packet walks reduce a
/// packet's bounds and hits with it several times a packet, and the lane-by-lane loop it replaced
/// (a chain of 16 dependent compares at 16 lanes) took a tenth of the wide BVH's packet walk.
/// min is exact, so the order of the tree does not change the value (a +0 and a -0 compare
/// equal, and either may come out, as in the loop).
template <class Arch>
float horizontal_min(const xsimd::batch<float, Arch>& x) {
    using Float = xsimd::batch<float, Arch>;
    const Float finite_or_inf = xsimd::select(x == x, x, Float(std::numeric_limits<float>::infinity()));
    // Types and masks spelled through Arch: a baseline file's headers do not declare __m512.
    using Register = typename Float::register_type;
    const Register all = finite_or_inf;
    __m128 quarter;
    if constexpr (kHasMaskRegisters<Arch>) {
        // Zero-masking forms throughout: gcc 12's plain AVX-512 shuffles, min and 512-to-128 cast
        // start from an undefined register and trip -Wmaybe-uninitialized once inlined.
        const auto all_lanes = xsimd::batch_bool<float, Arch>(true).data;
        const Register halves = _mm512_maskz_min_ps(all_lanes, all,
                                                    _mm512_maskz_shuffle_f32x4(all_lanes, all, all, _MM_SHUFFLE(1, 0, 3, 2)));
        const Register quarters = _mm512_maskz_min_ps(
            all_lanes, halves, _mm512_maskz_shuffle_f32x4(all_lanes, halves, halves, _MM_SHUFFLE(2, 3, 0, 1)));
        quarter = _mm512_maskz_extractf32x4_ps(static_cast<unsigned char>(0xF), quarters, 0);
    } else if constexpr (kIs256Bit<Arch>) {
        quarter = _mm_min_ps(_mm256_castps256_ps128(all), _mm256_extractf128_ps(all, 1));
    } else {
        static_assert(kIs128Bit<Arch>, "no mask helpers for this architecture");
        quarter = all;
    }
    const __m128 pair = _mm_min_ps(quarter, _mm_movehl_ps(quarter, quarter));
    return _mm_cvtss_f32(_mm_min_ss(pair, _mm_shuffle_ps(pair, pair, 1)));
}

}  // namespace trident::simd
