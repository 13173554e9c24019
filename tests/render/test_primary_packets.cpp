#include <doctest/doctest.h>

#include <cstring>
#include <vector>

#include "render/primary_packets.h"
#include "simd/width.h"

using namespace trident;

namespace {

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof(float)) == 0; }

/// Every block of `tile` at the width: each active lane's ray is primary_ray of its pixel bit for
/// bit, exactly the tile's pixels are active, and store() writes each lane's hit to its pixel and
/// nothing else.
template <SimdWidth W>
void check_blocks(const Camera& camera, const ImageTile& tile) {
    using Arch = ArchOf<W>;
    using Block = PrimaryBlock<Arch>;
    std::vector<Hit> image(std::size_t(camera.width()) * camera.height());
    std::size_t wrong_rays = 0, wrong_activity = 0;
    std::size_t blocks = 0;
    for_each_primary_block<Arch>(camera, tile, [&](const Block& block) {
        ++blocks;
        const RayPacket<Arch> rays = block.rays();
        const auto dx = Lanes<typename Block::Float>::to_array(rays.dir.x);
        const auto dy = Lanes<typename Block::Float>::to_array(rays.dir.y);
        const auto dz = Lanes<typename Block::Float>::to_array(rays.dir.z);
        const std::uint32_t active = simd::mask_bits(rays.active);
        HitPacket<Arch> hits(rays);
        alignas(64) std::array<std::uint32_t, Block::kLanes> ids;
        for (std::size_t i = 0; i < Block::kLanes; ++i) {
            const std::uint32_t x = block.x0 + std::uint32_t(i) % Block::kBlockWidth;
            const std::uint32_t y = block.y0 + std::uint32_t(i) / Block::kBlockWidth;
            const bool inside = x < tile.x1 && y < tile.y1;
            wrong_activity += inside != bool(active >> i & 1u);
            ids[i] = inside ? y * camera.width() + x : kNoTriangle;  // each lane "hits" its own pixel number
            if (!inside) continue;
            const Ray ray = camera.primary_ray(x, y);
            wrong_rays += !(same_bits(dx[i], ray.dir.x) && same_bits(dy[i], ray.dir.y) && same_bits(dz[i], ray.dir.z));
        }
        hits.triangle = HitPacket<Arch>::Ids::load_aligned(ids.data());
        block.store(hits, tile, camera.width(), image);
    });
    const auto blocks_across = (tile.x1 - tile.x0 + Block::kBlockWidth - 1) / Block::kBlockWidth;
    const auto blocks_down = (tile.y1 - tile.y0 + Block::kBlockHeight - 1) / Block::kBlockHeight;
    CHECK(blocks == std::size_t(blocks_across) * blocks_down);
    CHECK(wrong_rays == 0);
    CHECK(wrong_activity == 0);
    std::size_t wrong_pixels = 0;
    for (std::uint32_t y = 0; y < camera.height(); ++y)
        for (std::uint32_t x = 0; x < camera.width(); ++x) {
            const bool inside = x >= tile.x0 && x < tile.x1 && y >= tile.y0 && y < tile.y1;
            const TriangleId expected = inside ? y * camera.width() + x : kNoTriangle;
            wrong_pixels += image[std::size_t(y) * camera.width() + x].triangle != expected;
        }
    CHECK(wrong_pixels == 0);
}

}  // namespace

TEST_CASE("packet blocks of primary rays are the single rays bit for bit, active inside the tile only") {
    const Camera camera(CameraSpec{{1, 2, 3}, {1.5f, 2.25f, 2}, {0, 1, 0.5f}, 52.0f}, 1920, 1080);
    // A whole interior tile, and tiles cut by the image's right and bottom edges at sizes no packet
    // block divides.
    const Camera edge_camera(CameraSpec{{1, 2, 3}, {1.5f, 2.25f, 2}, {0, 1, 0.5f}, 52.0f}, 37, 23);
    for (SimdWidth width : {SimdWidth::w4, SimdWidth::w8, SimdWidth::w16}) {
        if (!is_runnable(width)) continue;
        CAPTURE(to_string(width));
        dispatch_width(width, [&]<SimdWidth W>() {
            if constexpr (W != SimdWidth::scalar && kArchInThisFile<W>) {
                check_blocks<W>(camera, tile_at(camera, 1234));
                check_blocks<W>(camera, ImageTile{1904, 1072, 1920, 1080});
                for (std::size_t t = 0; t < tile_count(edge_camera); ++t)
                    check_blocks<W>(edge_camera, tile_at(edge_camera, t));
            }
        });
    }
}
