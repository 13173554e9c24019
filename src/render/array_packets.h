#pragma once
// Packets of rays kept in arrays (render/ray_arrays.h), a block of an image of rays at a time, the
// check that every ray can be traced folded into the load. Copying each ray out of the arrays into
// a list, checking the list and packing packets from it took 40% of a Python batch's time on the
// study's Teapot against the traversal's 40% (perf, 16 lanes); here each lane is read once,
// straight from the arrays into the packet's lanes, and its result written once, to its place.
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <tuple>
#include <xsimd/xsimd.hpp>

#include "render/image_tiles.h"
#include "render/ray_arrays.h"
#include "simd/hit_lanes.h"
#include "simd/packet.h"

namespace trident {

/// The packet blocks of one tile of an image of rays, and where a block's lanes lie in the
/// arrays: lane i is pixel (x0 + i % block width, y0 + i / block width) of the block with top-left
/// pixel (x0, y0). Lanes whose pixel lies outside the tile are inactive and load the block's first
/// ray.
template <class Arch>
class ArrayTile {
public:
    using Float = xsimd::batch<float, Arch>;
    using Mask = xsimd::batch_bool<float, Arch>;
    static constexpr std::size_t kLanes = Float::size;
    static constexpr std::uint32_t kAllLanes = (1u << kLanes) - 1;

    ArrayTile(const RayImage& image, const ImageTile& tile) : image_(image), tile_(tile) {
        std::tie(block_width_, block_height_) = image.block(kLanes);
        alignas(64) std::array<float, kLanes> column, row;
        for (std::size_t i = 0; i < kLanes; ++i) {
            column[i] = float(i % block_width_), row[i] = float(i / block_width_);
            ray_offset_[i] = image.index(std::uint32_t(i % block_width_), std::uint32_t(i / block_width_));
            origin_offset_[i] = ray_offset_[i] * image.rays.origin_stride;
            direction_offset_[i] = ray_offset_[i] * image.rays.direction_stride;
        }
        column_ = Float::load_aligned(column.data()), row_ = Float::load_aligned(row.data());
        const StridedRays& rays = image.rays;
        six_float_rays_ = rays.origin_stride == 6 && rays.direction_stride == 6 && rays.directions == rays.origins + 3;
    }

    /// A packet block: its top-left pixel's ray and its active lanes (bit i: lane i).
    struct Block {
        std::size_t first;
        Mask active;
        std::uint32_t active_bits;
    };

    /// per_block(packet, block) for the tile's packet blocks, row by row, while it returns true;
    /// false when it returned false or at the first block holding a ray that cannot be traced
    /// (is_traceable, lane by lane in the same arithmetic), which is not traced.
    template <class PerBlock>
    bool for_each_block(PerBlock&& per_block) const {
        std::uint32_t x0 = tile_.x0, y0 = tile_.y0;
        Block block = block_at(x0, y0);
        BlockRays rays = load(block);
        for (;;) {
            const Mask active = block.active;
            if (xsimd::any(active & ~traceable(rays))) return false;
            // Made here, not returned in an optional: copying a packet's mask and octant fields
            // as whole vectors stalled on their narrow stores (perf).
            const RayPacket<Arch> packet(rays.origin, rays.dir, Float(image_.rays.tmin), Float(image_.rays.tmax),
                                         active);
            const Block traced = block;
            x0 += block_width_;
            if (x0 >= tile_.x1) x0 = tile_.x0, y0 += block_height_;
            const bool more = y0 < tile_.y1;
            // The next block's rays are read before this packet's walk and the stores of its
            // results: read after them, a 1920x1080 Teapot batch took 2-3% longer (one thread,
            // A/B), and prefetching them a block or four ahead instead did not help.
            if (more) {
                block = block_at(x0, y0);
                rays = load(block);
            }
            if (!per_block(packet, traced)) return false;
            if (!more) return true;
        }
    }

    /// The block's active lanes' hits to their rays' places in `out`, from registers
    /// (simd/hit_lanes.h), by streaming stores where the image asks for them
    /// (RayImage::stream_results).
    [[gnu::always_inline]] void store(const Block& block, const simd::HitLanes<Arch>& hits, Hit* out) const {
        Hit* const first = out + block.first;
        if (image_.stream_results)
            for_each_active_lane(block,
                                 [&](std::size_t i) { hits.template store_lane<true>(i, first + ray_offset_[i]); });
        else
            for_each_active_lane(block, [&](std::size_t i) { hits.store_lane(i, first + ray_offset_[i]); });
    }

    /// The block's active lanes' occlusion flags (bit i: lane i occluded) to their rays' places in
    /// `out`.
    [[gnu::always_inline]] void store(const Block& block, std::uint32_t occluded_bits, std::uint8_t* out) const {
        for_each_active_lane(block,
                             [&](std::size_t i) { out[block.first + ray_offset_[i]] = (occluded_bits >> i) & 1u; });
    }

private:
    template <class PerLane>
    [[gnu::always_inline]] static void for_each_active_lane(const Block& block, PerLane&& per_lane) {
        if (block.active_bits == kAllLanes) {
            for (std::size_t i = 0; i < kLanes; ++i) per_lane(i);
            return;
        }
        for (std::uint32_t bits = block.active_bits; bits != 0; bits &= bits - 1) per_lane(std::countr_zero(bits));
    }

    /// Each lane's 3 floats from at(i), by coordinate.
    template <class At>
    static Vec3T<Float> load_lanes(At&& at) {
#if defined(__AVX__)
        // Four lanes at a time: each lane's x, y, z in one register (the fourth float not read),
        // the four transposed, and the groups joined. Stored float by float and loaded as
        // vectors, the loads waited on the stores: perf counted a fifth more samples in the packet
        // loop on a Teapot batch.
        Quarters x, y, z;
        for (std::size_t g = 0; g < kLanes / 4; ++g) {
            __m128 r[4];
            for (std::size_t k = 0; k < 4; ++k) r[k] = load3(at(4 * g + k));
            _MM_TRANSPOSE4_PS(r[0], r[1], r[2], r[3]);
            x.part[g] = r[0], y.part[g] = r[1], z.part[g] = r[2];
        }
        return {join(x), join(y), join(z)};
#else
        alignas(64) std::array<float, kLanes> x, y, z;
        for (std::size_t i = 0; i < kLanes; ++i) {
            const float* p = at(i);
            x[i] = p[0], y[i] = p[1], z[i] = p[2];
        }
        return {Float::load_aligned(x.data()), Float::load_aligned(y.data()), Float::load_aligned(z.data())};
#endif
    }

#if defined(__AVX__)
    struct Quarters {
        __m128 part[kLanes / 4];
    };

    /// p[0..2] and a zero; p[3] is not read, so the array's last ray may end a page.
    static __m128 load3(const float* p) {
#if defined(__AVX512VL__)
        return _mm_maskz_loadu_ps(__mmask8(0x7), p);
#else
        return _mm_maskload_ps(p, _mm_setr_epi32(-1, -1, -1, 0));
#endif
    }

    static Float join(const Quarters& q) {
        if constexpr (kLanes == 4) {
            return q.part[0];
        } else if constexpr (kLanes == 8) {
            return _mm256_insertf128_ps(_mm256_castps128_ps256(q.part[0]), q.part[1], 1);
        } else {
            const __m512 low = _mm512_insertf32x4(_mm512_castps128_ps512(q.part[0]), q.part[1], 1);
            return _mm512_insertf32x4(_mm512_insertf32x4(low, q.part[2], 2), q.part[3], 3);
        }
    }
#endif

    Block block_at(std::uint32_t x0, std::uint32_t y0) const {
        // Small whole numbers, exact in floats: a lane is inside when its column and row in the
        // block are below the tile's remaining columns and rows.
        const Mask active = (column_ < Float(float(tile_.x1 - x0))) & (row_ < Float(float(tile_.y1 - y0)));
        return {image_.index(x0, y0), active, simd::mask_bits(active)};
    }

    struct BlockRays {
        Vec3T<Float> origin, dir;
    };

    [[gnu::always_inline]] BlockRays load(const Block& block) const {
        const float* origins = image_.rays.origins + block.first * image_.rays.origin_stride;
        const float* directions = image_.rays.directions + block.first * image_.rays.direction_stride;
#if defined(__AVX512F__)
        if constexpr (kLanes == 8 && kHasAvx512Dq)
            if (block.active_bits == kAllLanes && six_float_rays_) return load_six_float_rays(origins);
#endif
        if (block.active_bits == kAllLanes)
            return {load_lanes([&](std::size_t i) { return origins + origin_offset_[i]; }),
                    load_lanes([&](std::size_t i) { return directions + direction_offset_[i]; })};
        // Inactive lanes load the block's first ray.
        auto lane = [&](std::size_t i) { return (block.active_bits >> i) & 1u ? i : 0; };
        return {load_lanes([&](std::size_t i) { return origins + origin_offset_[lane(i)]; }),
                load_lanes([&](std::size_t i) { return directions + direction_offset_[lane(i)]; })};
    }

#if defined(__AVX512F__)
#if defined(__AVX512DQ__)
    static constexpr bool kHasAvx512Dq = true;  // for the 256-bit extracts below
#else
    static constexpr bool kHasAvx512Dq = false;
#endif

    /// A full 8-lane block of rays laid out as numpy's (..., 6) arrays (origin then direction,
    /// each ray's six floats after the last's), where AVX-512 runs the 8-lane packets: each 4
    /// lanes' 24 floats in two loads, permuted into fields. 3% less time than load_lanes on a
    /// 1920x1080 Teapot batch (one thread, A/B); the same done for 16 lanes took 4% more.
    BlockRays load_six_float_rays(const float* first) const {
        // Lanes 4r..4r+3 are consecutive rays: an image block's row r, or a run's r-th four.
        // p[r]: their fields ox, oy, oz, dx by 128-bit quarter (field f of ray k at 4f + k);
        // q[r]: dy and dz in quarters 0 and 1.
        const __m512i fields_0_to_3 = _mm512_setr_epi32(0, 6, 12, 18, 1, 7, 13, 19, 2, 8, 14, 20, 3, 9, 15, 21);
        const __m512i fields_4_and_5 = _mm512_setr_epi32(4, 10, 16, 22, 5, 11, 17, 23, 0, 0, 0, 0, 0, 0, 0, 0);
        __m512 p[2], q[2];
        for (std::size_t r = 0; r < 2; ++r) {
            const float* rays = first + origin_offset_[4 * r];
            const __m512 low = _mm512_loadu_ps(rays);
            const __m512 high = _mm512_maskz_loadu_ps(__mmask16(0x00FF), rays + 16);  // floats 16..23 only
            p[r] = _mm512_permutex2var_ps(low, fields_0_to_3, high);
            q[r] = _mm512_permutex2var_ps(low, fields_4_and_5, high);
        }
        // Quarter f of p[0] and of p[1] side by side is field f's 8 lanes, two fields a register.
        // The zero-masked forms with every lane kept: GCC 12 warns -Wmaybe-uninitialized inside
        // the unmasked ones and the casts to 256 bits (simd/lanes.h says the same of min and max).
        auto fields = [](const __m512& a, const __m512& b, bool high_quarters) {
            const __m512 pair = high_quarters
                                    ? _mm512_maskz_shuffle_f32x4(__mmask16(0xFFFF), a, b, 0xEE)   // 2, 3, 2, 3
                                    : _mm512_maskz_shuffle_f32x4(__mmask16(0xFFFF), a, b, 0x44);  // 0, 1, 0, 1
            return _mm512_maskz_shuffle_f32x4(__mmask16(0xFFFF), pair, pair, 0xD8);               // quarters 0, 2, 1, 3
        };
        auto low = [](const __m512& x) -> Float { return _mm512_maskz_extractf32x8_ps(__mmask8(0xFF), x, 0); };
        auto high = [](const __m512& x) -> Float { return _mm512_maskz_extractf32x8_ps(__mmask8(0xFF), x, 1); };
        const __m512 f01 = fields(p[0], p[1], false), f23 = fields(p[0], p[1], true), f45 = fields(q[0], q[1], false);
        return {{low(f01), high(f01), low(f23)}, {high(f23), low(f45), high(f45)}};
    }
#endif

    /// is_traceable lane by lane, in the same arithmetic.
    static Mask traceable(const BlockRays& rays) {
        const Float infinity(kInfinity);
        auto finite = [&](const Vec3T<Float>& v) {
            return (xsimd::abs(v.x) < infinity) & (xsimd::abs(v.y) < infinity) & (xsimd::abs(v.z) < infinity);
        };
        return finite(rays.origin) & finite(rays.dir) & (dot(rays.dir, rays.dir) > Float(0.0f));
    }

    const RayImage& image_;
    ImageTile tile_;
    std::uint32_t block_width_, block_height_;
    std::array<std::size_t, kLanes> ray_offset_;                        // lane i's ray from the block's first, in rays
    std::array<std::size_t, kLanes> origin_offset_, direction_offset_;  // the same in floats
    Float column_, row_;                                                // lane i's place in the block
    bool six_float_rays_;                                               // rays as numpy's (..., 6) arrays lay them out
};

}  // namespace trident
