#pragma once
// A packet's hits out as scalar Hits by a register transpose, the reverse of ray_lanes.h: a Hit
// is four 32-bit fields (triangle, t, u, v), so a 4 x 4 transpose within each 128-bit lane of the
// four field batches leaves every lane's Hit whole in one 128-bit lane, written with one store, or
// a row of four lanes with one 512-bit (two 256-bit) stores. HitPacket::store went through arrays
// filled by the field batches and read back a lane at a time, then copied again into the image.
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <xsimd/xsimd.hpp>

#include "core/ray.h"
#include "simd/mask.h"
#include "simd/packet.h"

namespace trident::simd {

static_assert(sizeof(Hit) == 4 * sizeof(float) && offsetof(Hit, t) == 4 && offsetof(Hit, u) == 8 &&
                  offsetof(Hit, v) == 12,
              "a Hit is its four 32-bit fields in this order, which the transposes write");

/// Writes the packet's lanes as Hits, a miss (triangle kNoTriangle) as Hit{}. Lane 4j + k's Hit
/// is 128-bit lane j of quad[k] (at 4 lanes, quad[k] is lane k's).
template <class Arch>
class HitLanes {
    using Register = typename xsimd::batch<float, Arch>::register_type;

public:
    static constexpr std::size_t width = HitPacket<Arch>::width;

    // The wider branches are compiled only where their instruction set is (the portable build
    // compiles this header for each kernel file's own), and only such files make their batches.
    explicit HitLanes(const HitPacket<Arch>& hits) {
        using Ids = typename xsimd::batch<std::uint32_t, Arch>::register_type;
        const Ids ids = hits.triangle;
        const Register t = hits.t, u = hits.u, v = hits.v;
        if constexpr (kHasMaskRegisters<Arch>) {
#if XSIMD_WITH_AVX512F
            // Zero-masking forms where gcc 12's plain ones start from an undefined register and
            // trip -Wmaybe-uninitialized (mask.h).
            const __mmask16 all = 0xFFFF;
            const __mmask16 hit = _mm512_cmpneq_epi32_mask(ids, _mm512_set1_epi32(int(kNoTriangle)));
            const Register id = _mm512_castsi512_ps(ids);
            const Register hit_t = _mm512_mask_blend_ps(hit, _mm512_set1_ps(kInfinity), t);
            const Register hit_u = _mm512_maskz_mov_ps(hit, u), hit_v = _mm512_maskz_mov_ps(hit, v);
            const Register id_t_lo = _mm512_maskz_unpacklo_ps(all, id, hit_t);  // id0 t0 id1 t1
            const Register id_t_hi = _mm512_maskz_unpackhi_ps(all, id, hit_t);  // id2 t2 id3 t3
            const Register uv_lo = _mm512_maskz_unpacklo_ps(all, hit_u, hit_v);
            const Register uv_hi = _mm512_maskz_unpackhi_ps(all, hit_u, hit_v);
            quad_[0] = _mm512_shuffle_ps(id_t_lo, uv_lo, _MM_SHUFFLE(1, 0, 1, 0));
            quad_[1] = _mm512_shuffle_ps(id_t_lo, uv_lo, _MM_SHUFFLE(3, 2, 3, 2));
            quad_[2] = _mm512_shuffle_ps(id_t_hi, uv_hi, _MM_SHUFFLE(1, 0, 1, 0));
            quad_[3] = _mm512_shuffle_ps(id_t_hi, uv_hi, _MM_SHUFFLE(3, 2, 3, 2));
#else
            static_assert(sizeof(Arch) == 0, "AVX-512 batches in a file compiled without AVX-512");
#endif
        } else if constexpr (kIs256Bit<Arch>) {
#if XSIMD_WITH_AVX2
            const Register miss = _mm256_castsi256_ps(_mm256_cmpeq_epi32(ids, _mm256_set1_epi32(int(kNoTriangle))));
            const Register id = _mm256_castsi256_ps(ids);
            const Register hit_t = _mm256_blendv_ps(t, _mm256_set1_ps(kInfinity), miss);
            const Register hit_u = _mm256_andnot_ps(miss, u), hit_v = _mm256_andnot_ps(miss, v);
            const Register id_t_lo = _mm256_unpacklo_ps(id, hit_t), id_t_hi = _mm256_unpackhi_ps(id, hit_t);
            const Register uv_lo = _mm256_unpacklo_ps(hit_u, hit_v), uv_hi = _mm256_unpackhi_ps(hit_u, hit_v);
            quad_[0] = _mm256_shuffle_ps(id_t_lo, uv_lo, _MM_SHUFFLE(1, 0, 1, 0));
            quad_[1] = _mm256_shuffle_ps(id_t_lo, uv_lo, _MM_SHUFFLE(3, 2, 3, 2));
            quad_[2] = _mm256_shuffle_ps(id_t_hi, uv_hi, _MM_SHUFFLE(1, 0, 1, 0));
            quad_[3] = _mm256_shuffle_ps(id_t_hi, uv_hi, _MM_SHUFFLE(3, 2, 3, 2));
#else
            static_assert(sizeof(Arch) == 0, "AVX2 batches in a file compiled without AVX2");
#endif
        } else {
            static_assert(kIs128Bit<Arch> && width == 4);
            const Register miss = _mm_castsi128_ps(_mm_cmpeq_epi32(ids, _mm_set1_epi32(int(kNoTriangle))));
            quad_[0] = _mm_castsi128_ps(ids);
            quad_[1] = _mm_blendv_ps(t, _mm_set1_ps(kInfinity), miss);
            quad_[2] = _mm_andnot_ps(miss, u);
            quad_[3] = _mm_andnot_ps(miss, v);
            _MM_TRANSPOSE4_PS(quad_[0], quad_[1], quad_[2], quad_[3]);
        }
    }

    /// Every row of the packet's pixel block (image_tiles.h): lanes 4 * r to 4 * r + 3 to
    /// row_start(r)[0..3] (8 and 16 lanes), or lanes 2 * r and 2 * r + 1 to row_start(r)[0..1]
    /// (4 lanes). All rows at once, as the 16-lane rows share their first shuffles, and with every
    /// shuffle's selector written out: it must be an immediate at every optimization level.
    template <std::size_t RowLanes, class RowStart>
    void store_rows(RowStart&& row_start) const {
        const auto to = [&](std::size_t row) { return reinterpret_cast<float*>(row_start(row)); };
        if constexpr (kHasMaskRegisters<Arch>) {
            static_assert(RowLanes == 4);
#if XSIMD_WITH_AVX512F
            // Row j is 128-bit lane j of quad_[0..3]: a 4 x 4 transpose of 128-bit lanes.
            const __mmask16 all = 0xFFFF;
            const Register low_01 = _mm512_maskz_shuffle_f32x4(all, quad_[0], quad_[1], 0x44);  // 128-bit lanes 0, 1
            const Register low_23 = _mm512_maskz_shuffle_f32x4(all, quad_[2], quad_[3], 0x44);
            const Register high_01 = _mm512_maskz_shuffle_f32x4(all, quad_[0], quad_[1], 0xEE);  // lanes 2, 3
            const Register high_23 = _mm512_maskz_shuffle_f32x4(all, quad_[2], quad_[3], 0xEE);
            _mm512_storeu_ps(to(0), _mm512_maskz_shuffle_f32x4(all, low_01, low_23, 0x88));
            _mm512_storeu_ps(to(1), _mm512_maskz_shuffle_f32x4(all, low_01, low_23, 0xDD));
            _mm512_storeu_ps(to(2), _mm512_maskz_shuffle_f32x4(all, high_01, high_23, 0x88));
            _mm512_storeu_ps(to(3), _mm512_maskz_shuffle_f32x4(all, high_01, high_23, 0xDD));
#endif
        } else if constexpr (kIs256Bit<Arch>) {
            static_assert(RowLanes == 4);
#if XSIMD_WITH_AVX2
            _mm256_storeu_ps(to(0), _mm256_permute2f128_ps(quad_[0], quad_[1], 0x20));
            _mm256_storeu_ps(to(0) + 8, _mm256_permute2f128_ps(quad_[2], quad_[3], 0x20));
            _mm256_storeu_ps(to(1), _mm256_permute2f128_ps(quad_[0], quad_[1], 0x31));
            _mm256_storeu_ps(to(1) + 8, _mm256_permute2f128_ps(quad_[2], quad_[3], 0x31));
#endif
        } else {
            static_assert(RowLanes == 2);
            for (std::size_t row = 0; row < 2; ++row) {
                _mm_storeu_ps(to(row), quad_[2 * row]);
                _mm_storeu_ps(to(row) + 4, quad_[2 * row + 1]);
            }
        }
    }

    /// Lane i's Hit to *out; Streaming: by a streaming store, which bypasses the caches (out
    /// 16-byte aligned; render/ray_arrays.h says when).
    template <bool Streaming = false>
    void store_lane(std::size_t i, Hit* out) const {
        assert(i < width);
        __m128 hit;
        if constexpr (kHasMaskRegisters<Arch>) {
#if XSIMD_WITH_AVX512F
            const Register& quad = quad_[i % 4];
            const __mmask8 all = 0xF;
            switch (i / 4) {  // the 128-bit lane is an immediate of the extract
                case 0:
                    hit = _mm512_maskz_extractf32x4_ps(all, quad, 0);
                    break;
                case 1:
                    hit = _mm512_maskz_extractf32x4_ps(all, quad, 1);
                    break;
                case 2:
                    hit = _mm512_maskz_extractf32x4_ps(all, quad, 2);
                    break;
                default:
                    hit = _mm512_maskz_extractf32x4_ps(all, quad, 3);
                    break;
            }
#endif
        } else if constexpr (kIs256Bit<Arch>) {
#if XSIMD_WITH_AVX2
            const Register& quad = quad_[i % 4];
            hit = i < 4 ? _mm256_castps256_ps128(quad) : _mm256_extractf128_ps(quad, 1);
#endif
        } else {
            hit = quad_[i];
        }
        float* const to = reinterpret_cast<float*>(out);
        if constexpr (Streaming)
            _mm_stream_ps(to, hit);
        else
            _mm_storeu_ps(to, hit);
    }

private:
    Register quad_[4];  // a plain array: std::array of a vector type drops its attributes
};

}  // namespace trident::simd
