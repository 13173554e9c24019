#include "render/gamma.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

namespace trident {

std::uint8_t gamma_byte_formula(float linear) {
    const float encoded = std::pow(std::clamp(linear, 0.0f, 1.0f), 1.0f / 2.2f);
    return std::uint8_t(std::lround(encoded * 255.0f));
}

namespace {

/// Where the byte steps up, and where to start looking. steps[k - 1] is the least float of [0, 1]
/// whose byte is at least k (steps[255] = +inf: none is 256). start[j] is the byte of the least
/// float whose bit pattern has j as its top 16 bits; within those 65536 floats the byte steps up
/// at most once, since the gamma curve is flattest where they are widest (between 0.5 and 1 they
/// span 0.0039, about 0.66 of a byte), so one compare finishes the lookup.
struct GammaTable {
    std::array<float, 256> steps{};
    std::vector<std::uint8_t> start;
};

/// Non-negative floats order as their bit patterns, so each step is a binary search over the
/// patterns from 0 to 1. That needs a formula that never decreases as its argument grows, which
/// holds: every float of [0, 1] gives the formula's byte (checked once over all of them; samples
/// and every step in tests/render/test_gamma.cpp).
GammaTable make_table() {
    GammaTable table;
    for (int k = 1; k <= 255; ++k) {
        std::uint32_t low = std::bit_cast<std::uint32_t>(0.0f), high = std::bit_cast<std::uint32_t>(1.0f);
        while (low < high) {  // the least pattern in [low, high] whose byte is at least k
            const std::uint32_t middle = low + (high - low) / 2;
            if (gamma_byte_formula(std::bit_cast<float>(middle)) >= k)
                high = middle;
            else
                low = middle + 1;
        }
        table.steps[k - 1] = std::bit_cast<float>(low);
    }
    table.steps[255] = std::numeric_limits<float>::infinity();
    const std::uint32_t last = std::bit_cast<std::uint32_t>(1.0f) >> 16;
    table.start.resize(last + 1);
    for (std::uint32_t j = 0; j <= last; ++j) table.start[j] = gamma_byte_formula(std::bit_cast<float>(j << 16));
    return table;
}

}  // namespace

std::uint8_t gamma_byte(float linear) {
    static const GammaTable table = make_table();
    if (!(linear > 0.0f)) return 0;  // also NaN
    const float x = std::min(linear, 1.0f);
    const std::uint8_t start = table.start[std::bit_cast<std::uint32_t>(x) >> 16];
    return std::uint8_t(start + (x >= table.steps[start] ? 1 : 0));
}

}  // namespace trident
