#pragma once
// The image as a grid of square tiles from its top-left corner: the unit of work the renderer
// hands to threads, for primary and secondary rays alike. Tile edges fall on multiples of the
// tile size, a multiple of every packet block, so packets are cut only at the image's edges.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstddef>
#include <cstdint>
#include <utility>

#include "camera/camera.h"

namespace trident {

/// Side of the square image tiles; a multiple of every packet block.
inline constexpr std::uint32_t kRenderTileSize = 16;

/// Pixels per packet: width x height of the block a packet of `lanes` rays covers.
constexpr std::pair<std::uint32_t, std::uint32_t> packet_block(std::size_t lanes) {
    return lanes == 4 ? std::pair{2u, 2u} : std::pair{4u, std::uint32_t(lanes / 4)};
}
static_assert([] {
    for (const std::size_t lanes : {4, 8, 16})
        if (kRenderTileSize % packet_block(lanes).first != 0 || kRenderTileSize % packet_block(lanes).second != 0)
            return false;
    return true;
}());

struct ImageTile {
    std::uint32_t x0, y0, x1, y1;  // [x0, x1) x [y0, y1)
};

std::size_t tile_count(const Camera& camera);
/// Tile `index` in row-major order.
ImageTile tile_at(const Camera& camera, std::size_t index);
/// Runs per_tile(ImageTile) over the image's tiles on oneTBB's threads. A tile's work depends only on
/// the tile, so results do not change with the thread count or the order tiles run in.
template <class PerTile>
void for_each_image_tile(const Camera& camera, PerTile&& per_tile) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tile_count(camera)), [&](const auto& range) {
        for (std::size_t t = range.begin(); t != range.end(); ++t) per_tile(tile_at(camera, t));
    });
}

}  // namespace trident
