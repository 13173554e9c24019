#include "render/image_tiles.h"

#include <algorithm>

namespace trident {

std::size_t tile_count(const Camera& camera) {
    const std::size_t across = (camera.width() + kRenderTileSize - 1) / kRenderTileSize;
    const std::size_t down = (camera.height() + kRenderTileSize - 1) / kRenderTileSize;
    return across * down;
}

ImageTile tile_at(const Camera& camera, std::size_t index) {
    const std::size_t across = (camera.width() + kRenderTileSize - 1) / kRenderTileSize;
    const auto x0 = std::uint32_t(index % across) * kRenderTileSize;
    const auto y0 = std::uint32_t(index / across) * kRenderTileSize;
    return {x0, y0, std::min(x0 + kRenderTileSize, camera.width()), std::min(y0 + kRenderTileSize, camera.height())};
}

}  // namespace trident
