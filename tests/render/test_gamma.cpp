#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "render/gamma.h"

using namespace trident;

namespace {

float from_bits(std::uint32_t bits) { return std::bit_cast<float>(bits); }

}  // namespace

// The table must give the formula's byte for every float. Every float of [0, 1] was checked once
// (about 1.07e9 values, all equal: a throwaway loop over the bit patterns, 2026-12-07); here every
// 1009th pattern, and around each place the byte steps up, found between two samples that differ
// by bisection, the float where it steps and the one below it.
TEST_CASE("gamma_byte gives the formula's byte, at every step exactly") {
    const std::uint32_t one = std::bit_cast<std::uint32_t>(1.0f);
    int steps_found = 0, mismatches = 0;
    std::uint32_t previous = 0;
    for (std::uint32_t bits = 0;; bits = std::min(one, bits + 1009)) {
        if (gamma_byte(from_bits(bits)) != gamma_byte_formula(from_bits(bits))) ++mismatches;
        if (bits > 0 && gamma_byte_formula(from_bits(previous)) != gamma_byte_formula(from_bits(bits))) {
            // Bisect (previous, bits] for the least pattern with the higher byte.
            std::uint32_t low = previous + 1, high = bits;
            const int below = gamma_byte_formula(from_bits(previous));
            while (low < high) {
                const std::uint32_t middle = low + (high - low) / 2;
                if (gamma_byte_formula(from_bits(middle)) > below)
                    high = middle;
                else
                    low = middle + 1;
            }
            if (gamma_byte(from_bits(low)) != gamma_byte_formula(from_bits(low))) ++mismatches;
            if (gamma_byte(from_bits(low - 1)) != gamma_byte_formula(from_bits(low - 1))) ++mismatches;
            steps_found += gamma_byte_formula(from_bits(low)) - below;
        }
        previous = bits;
        if (bits == one) break;
    }
    CHECK(mismatches == 0);
    CHECK(steps_found == 255);  // every byte from 0 to 255 is reached
}

TEST_CASE("gamma_byte clamps to [0, 1], and NaN gives 0") {
    CHECK(gamma_byte(0.0f) == 0);
    CHECK(gamma_byte(-0.0f) == 0);
    CHECK(gamma_byte(-1.0f) == 0);
    CHECK(gamma_byte(-std::numeric_limits<float>::infinity()) == 0);
    CHECK(gamma_byte(1.0f) == 255);
    CHECK(gamma_byte(7.5f) == 255);
    CHECK(gamma_byte(std::numeric_limits<float>::infinity()) == 255);
    CHECK(gamma_byte(std::numeric_limits<float>::quiet_NaN()) == 0);
    CHECK(gamma_byte(0.5f) == gamma_byte_formula(0.5f));
    CHECK(gamma_byte(0.5f) == 186);  // round(255 * 0.5^(1/2.2)) = round(186.1)
}
