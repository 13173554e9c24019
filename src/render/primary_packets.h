#pragma once
// Primary rays a packet at a time: the rays of one packet block (image_tiles.h) made in SIMD, one
// pixel per lane, and the packet's hits written back into the image row by row. Making each ray
// alone and gathering the lanes took two thirds as long as the 8-wide BVH traversal itself on
// the study's Teapot and Buddha (perf); Camera::primary_direction over a batch makes them all at
// once, bit for bit the single rays.
#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <xsimd/xsimd.hpp>

#include "camera/camera.h"
#include "render/image_tiles.h"
#include "simd/hit_lanes.h"
#include "simd/lanes.h"
#include "simd/packet.h"

namespace trident {

/// The lanes of the packet block with top-left pixel (x0, y0): lane i is pixel (x0 + i % block
/// width, y0 + i / block width). Lanes whose pixel lies outside `tile` are inactive; their
/// direction is that of the nearest pixel inside, so it is finite.
template <class Arch>
struct PrimaryBlock {
    using Float = xsimd::batch<float, Arch>;
    using Mask = xsimd::batch_bool<float, Arch>;
    static constexpr std::size_t kLanes = Float::size;
    static constexpr std::uint32_t kBlockWidth = packet_block(kLanes).first;
    static constexpr std::uint32_t kBlockHeight = packet_block(kLanes).second;

    std::uint32_t x0, y0;
    Vec3f origin;  // the camera's eye, every lane's origin
    Vec3T<Float> dir;
    Mask active;

    PrimaryBlock(const Camera& camera, const ImageTile& tile, std::uint32_t x0_, std::uint32_t y0_)
        : x0(x0_), y0(y0_), origin(camera.eye()) {
        const Float x = Float(float(x0)) + Float::load_aligned(kColumns.data());
        const Float y = Float(float(y0)) + Float::load_aligned(kRows.data());
        const Float last_x(float(tile.x1 - 1)), last_y(float(tile.y1 - 1));
        active = (x <= last_x) & (y <= last_y);
        // Whole numbers below 2^24 throughout, so every sum and comparison here is exact.
        dir = camera.primary_direction(Lanes<Float>::min(x, last_x), Lanes<Float>::min(y, last_y));
    }

    /// The block's rays (tmin 0, tmax +inf) as a packet.
    RayPacket<Arch> rays() const {
        return RayPacket<Arch>(Vec3T<Float>(origin), dir, Float(0.0f), Float(kInfinity), active);
    }

    /// f(x, y) for each of the block's pixels inside `tile`, row by row.
    template <class F>
    void for_each_pixel(const ImageTile& tile, F&& f) const {
        for (std::uint32_t y = y0; y < std::min(y0 + kBlockHeight, tile.y1); ++y)
            for (std::uint32_t x = x0; x < std::min(x0 + kBlockWidth, tile.x1); ++x) f(x, y);
    }

    /// The block's lanes of `hits` into the image `out` (row-major, `image_width` wide), inside
    /// `tile` only.
    void store(const HitPacket<Arch>& hits, const ImageTile& tile, std::uint32_t image_width,
               std::span<Hit> out) const {
        const simd::HitLanes<Arch> lanes(hits);
        const auto row_start = [&](std::size_t row) { return out.data() + (y0 + row) * image_width + x0; };
        // A whole block, as every block of an image whose sides the block's divide, row by row
        // from registers.
        if (x0 + kBlockWidth <= tile.x1 && y0 + kBlockHeight <= tile.y1) {
            lanes.template store_rows<kBlockWidth>(row_start);
            return;
        }
        for (std::uint32_t row = 0; row < kBlockHeight && y0 + row < tile.y1; ++row)
            for (std::uint32_t column = 0; column < kBlockWidth && x0 + column < tile.x1; ++column)
                lanes.store_lane(row * kBlockWidth + column, row_start(row) + column);
    }

private:
    /// Each lane's column and row within the block.
    static constexpr std::array<float, kLanes> lane_offsets(bool rows) {
        std::array<float, kLanes> out{};
        for (std::size_t i = 0; i < kLanes; ++i) out[i] = float(rows ? i / kBlockWidth : i % kBlockWidth);
        return out;
    }
    alignas(64) static constexpr std::array<float, kLanes> kColumns = lane_offsets(false), kRows = lane_offsets(true);
};

/// per_block(PrimaryBlock<Arch>) for each packet block of `tile`, row by row.
template <class Arch, class PerBlock>
void for_each_primary_block(const Camera& camera, const ImageTile& tile, PerBlock&& per_block) {
    using Block = PrimaryBlock<Arch>;
    for (std::uint32_t y0 = tile.y0; y0 < tile.y1; y0 += Block::kBlockHeight)
        for (std::uint32_t x0 = tile.x0; x0 < tile.x1; x0 += Block::kBlockWidth) per_block(Block(camera, tile, x0, y0));
}

}  // namespace trident
