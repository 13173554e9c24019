#include "accel/octree/morton_order.h"

#include <algorithm>
#include <array>
#include <bit>
#include <utility>

#include "core/morton.h"

namespace trident {

std::uint32_t morton_key(const Vec3f& point, const OctreeCube& cube) {
    constexpr float kCells = float(1u << kMortonBitsPerAxis);
    const float scale = cube.size > 0.0f ? kCells / cube.size : 0.0f;
    std::uint32_t cell[3];
    for (int axis = 0; axis < 3; ++axis)
        cell[axis] = std::uint32_t(std::clamp((point[axis] - cube.lo[axis]) * scale, 0.0f, kCells - 1.0f));
    return morton_code(cell[0], cell[1], cell[2]);
}

MortonSorted sort_by_morton_key(std::span<const Triangle> triangles, std::vector<std::uint32_t> indices,
                                const OctreeCube& cube) {
    std::vector<std::uint32_t> keys(indices.size());
    for (std::size_t i = 0; i < indices.size(); ++i) keys[i] = morton_key(triangles[indices[i]].centroid(), cube);
    // A least-significant-digit radix sort, 10 bits a pass.
    constexpr int kDigitBits = 10;
    constexpr int kKeyBits = 3 * kMortonBitsPerAxis;
    std::vector<std::uint32_t> indices_out(indices.size()), keys_out(keys.size());
    for (int shift = 0; shift < kKeyBits; shift += kDigitBits) {
        std::array<std::size_t, (1u << kDigitBits) + 1> start{};
        for (std::uint32_t key : keys) ++start[((key >> shift) & ((1u << kDigitBits) - 1)) + 1];
        for (std::size_t d = 1; d < start.size(); ++d) start[d] += start[d - 1];
        for (std::size_t i = 0; i < keys.size(); ++i) {
            const std::size_t to = start[(keys[i] >> shift) & ((1u << kDigitBits) - 1)]++;
            keys_out[to] = keys[i];
            indices_out[to] = indices[i];
        }
        keys.swap(keys_out);
        indices.swap(indices_out);
    }
    return {std::move(indices), std::move(keys)};
}

std::vector<std::size_t> occupied_cells_per_depth(std::span<const std::uint32_t> sorted_keys) {
    // Two neighbours fall apart at the depth of their first differing 3-bit digit and stay apart
    // below it; count, per depth, the neighbours that first fall apart there.
    std::vector<std::size_t> occupied(kMortonBitsPerAxis + 1, 0);
    if (sorted_keys.empty()) return occupied;
    for (std::size_t i = 1; i < sorted_keys.size(); ++i) {
        const std::uint32_t diff = sorted_keys[i] ^ sorted_keys[i - 1];
        if (diff == 0) continue;
        const int highest_bit = std::bit_width(diff) - 1;  // 0 .. 29
        ++occupied[std::size_t(kMortonBitsPerAxis - highest_bit / 3)];
    }
    occupied[0] = 1;
    for (std::size_t d = 1; d < occupied.size(); ++d) occupied[d] += occupied[d - 1];
    return occupied;
}

}  // namespace trident
