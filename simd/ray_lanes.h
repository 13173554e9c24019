#pragma once
// Rays into lanes by a register transpose: a Ray is eight floats (origin, direction, tmin, tmax),
// so each ray is one or two vector loads, and a transpose of those registers gives one batch per
// field. Filling eight arrays lane by lane and loading them as vectors made every load wait until
// the narrow stores behind it had retired (a wide load cannot take its bytes from several narrow
// stores in flight): 10% of Teapot's 8-lane shadow packets on the Zen 5 host (perf,
// bench/experiments/bvh-traversal.md).
#include <array>
#include <cassert>
#include <cstddef>
#include <span>
#include <xsimd/xsimd.hpp>

#include "core/ray.h"
#include "simd/mask.h"

namespace trident::simd {

static_assert(sizeof(Ray) == 8 * sizeof(float) && offsetof(Ray, dir) == 3 * sizeof(float) &&
                  offsetof(Ray, tmin) == 6 * sizeof(float) && offsetof(Ray, tmax) == 7 * sizeof(float),
              "a Ray is its eight floats in this order, which the transposes read");

/// The fields of up to a batch's width of rays, lane i from rays[i]; lanes past the count repeat
/// rays[0] (finite, in its octant) and are not `live`.
template <class Arch>
struct RayLanes {
    using Float = xsimd::batch<float, Arch>;
    using Mask = xsimd::batch_bool<float, Arch>;
    static constexpr std::size_t width = Float::size;
    /// ox, oy, oz, dx, dy, dz, tmin, tmax.
    std::array<Float, 8> field;
    Mask live;

    // The wider branches are compiled only where their instruction set is (the portable build
    // compiles this header for each kernel file's own), and only such files make their batches.
    explicit RayLanes(std::span<const Ray> rays) : RayLanes(rays.size(), [&](std::size_t i) { return &rays[i]; }) {}

    /// Lane i from rays[index[i]], read where the rays lie: a stream's packet, whose rays copied
    /// into a packet's array first would be stored and loaded again.
    RayLanes(std::span<const Ray> rays, std::span<const std::size_t> index)
        : RayLanes(index.size(), [&](std::size_t i) { return &rays[index[i]]; }) {}

private:
    /// Lane i from *ray_at(i), i < count.
    template <class RayAt>
    RayLanes(std::size_t count, RayAt&& ray_at) : live(first_lanes(count)) {
        assert(count != 0 && count <= width);
        // Ray i's eight floats (the static_assert above), ray 0's past the count.
        const auto ray = [&](std::size_t i) { return reinterpret_cast<const float*>(ray_at(i < count ? i : 0)); };
        if constexpr (kHasMaskRegisters<Arch>) {
            static_assert(width == 16);
            // Rays j and j + 8 share register j; the 8 x 8 transpose within each 256-bit half
            // leaves field f of rays 0-3, 4-7, 8-11, 12-15 spread over two registers' 128-bit
            // lanes, which one two-source permute per field puts in order.
#if XSIMD_WITH_AVX512F
            // Masked forms throughout: GCC 12 warns inside the plain ones (lanes.h). The halves are
            // joined as doubles, as AVX-512F has no float form of the insert.
            const __mmask16 all = 0xFFFF;
            __m512 r[8];
            for (std::size_t j = 0; j < 8; ++j)
                r[j] = _mm512_castpd_ps(_mm512_maskz_insertf64x4(
                    __mmask8(0xFF), _mm512_castps_pd(_mm512_castps256_ps512(_mm256_loadu_ps(ray(j)))),
                    _mm256_castps_pd(_mm256_loadu_ps(ray(j + 8))), 1));
            __m512 t[8], s[8];
            for (std::size_t j = 0; j < 8; j += 2) {
                t[j] = _mm512_maskz_unpacklo_ps(all, r[j], r[j + 1]);
                t[j + 1] = _mm512_maskz_unpackhi_ps(all, r[j], r[j + 1]);
            }
            // q: rays 0-3 (and 8-11), then 4-7 (and 12-15).
            for (std::size_t q = 0; q < 8; q += 4) {
                s[q] = _mm512_shuffle_ps(t[q], t[q + 2], _MM_SHUFFLE(1, 0, 1, 0));          // fields 0 and 4
                s[q + 1] = _mm512_shuffle_ps(t[q], t[q + 2], _MM_SHUFFLE(3, 2, 3, 2));      // 1 and 5
                s[q + 2] = _mm512_shuffle_ps(t[q + 1], t[q + 3], _MM_SHUFFLE(1, 0, 1, 0));  // 2 and 6
                s[q + 3] = _mm512_shuffle_ps(t[q + 1], t[q + 3], _MM_SHUFFLE(3, 2, 3, 2));  // 3 and 7
            }
            const __m512i low = _mm512_setr_epi32(0, 1, 2, 3, 16, 17, 18, 19, 8, 9, 10, 11, 24, 25, 26, 27);
            const __m512i high = _mm512_setr_epi32(4, 5, 6, 7, 20, 21, 22, 23, 12, 13, 14, 15, 28, 29, 30, 31);
            for (std::size_t f = 0; f < 4; ++f) {
                field[f] = _mm512_permutex2var_ps(s[f], low, s[f + 4]);
                field[f + 4] = _mm512_permutex2var_ps(s[f], high, s[f + 4]);
            }
#else
            static_assert(sizeof(Arch) == 0, "AVX-512 batches in a file compiled without AVX-512");
#endif
        } else if constexpr (kIs256Bit<Arch>) {
            static_assert(width == 8);
#if XSIMD_WITH_AVX
            __m256 r[8], t[8], s[8];
            for (std::size_t j = 0; j < 8; ++j) r[j] = _mm256_loadu_ps(ray(j));
            for (std::size_t j = 0; j < 8; j += 2) {
                t[j] = _mm256_unpacklo_ps(r[j], r[j + 1]);
                t[j + 1] = _mm256_unpackhi_ps(r[j], r[j + 1]);
            }
            // q: rays 0-3, then 4-7.
            for (std::size_t q = 0; q < 8; q += 4) {
                s[q] = _mm256_shuffle_ps(t[q], t[q + 2], _MM_SHUFFLE(1, 0, 1, 0));          // fields 0 and 4
                s[q + 1] = _mm256_shuffle_ps(t[q], t[q + 2], _MM_SHUFFLE(3, 2, 3, 2));      // 1 and 5
                s[q + 2] = _mm256_shuffle_ps(t[q + 1], t[q + 3], _MM_SHUFFLE(1, 0, 1, 0));  // 2 and 6
                s[q + 3] = _mm256_shuffle_ps(t[q + 1], t[q + 3], _MM_SHUFFLE(3, 2, 3, 2));  // 3 and 7
            }
            for (std::size_t f = 0; f < 4; ++f) {
                field[f] = _mm256_permute2f128_ps(s[f], s[f + 4], 0x20);
                field[f + 4] = _mm256_permute2f128_ps(s[f], s[f + 4], 0x31);
            }
#else
            static_assert(sizeof(Arch) == 0, "AVX batches in a file compiled without AVX");
#endif
        } else {
            static_assert(kIs128Bit<Arch> && width == 4);
            __m128 lo[4], hi[4];  // ox oy oz dx, and dy dz tmin tmax
            for (std::size_t j = 0; j < 4; ++j) lo[j] = _mm_loadu_ps(ray(j)), hi[j] = _mm_loadu_ps(ray(j) + 4);
            _MM_TRANSPOSE4_PS(lo[0], lo[1], lo[2], lo[3]);
            _MM_TRANSPOSE4_PS(hi[0], hi[1], hi[2], hi[3]);
            for (std::size_t f = 0; f < 4; ++f) field[f] = lo[f], field[f + 4] = hi[f];
        }
    }

    static Mask first_lanes(std::size_t count) { return lane_indices<Arch>() < Float(float(count)); }
};

}  // namespace trident::simd
