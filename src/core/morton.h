#pragma once
// Morton (Z-order) codes of 3D cells: the octree's cell order, and the order in which the KD-tree
// stores its triangles, so that triangles near in space are near in memory.
#include <cstdint>

namespace trident {

/// Spreads the low 10 bits of v so that bit i lands on bit 3i.
constexpr std::uint32_t spread_bits_3d(std::uint32_t v) {
    v &= 0x3FFu;
    v = (v | (v << 16)) & 0x030000FFu;
    v = (v | (v << 8)) & 0x0300F00Fu;
    v = (v | (v << 4)) & 0x030C30C3u;
    return (v | (v << 2)) & 0x09249249u;
}

/// The code of cell (x, y, z), each in [0, 1024): bit 3i + a holds bit i of the coordinate on axis a.
constexpr std::uint32_t morton_code(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return spread_bits_3d(x) | spread_bits_3d(y) << 1 | spread_bits_3d(z) << 2;
}

static_assert(morton_code(1, 0, 0) == 1 && morton_code(0, 1, 0) == 2 && morton_code(0, 0, 1) == 4);
static_assert(morton_code(1023, 1023, 1023) == (1u << 30) - 1);

}  // namespace trident
