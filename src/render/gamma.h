#pragma once
// Linear intensity to an 8-bit display value under gamma 2.2: round(255 * x^(1/2.2)) of x clamped
// to [0, 1]. Shading writes three per pixel, and powf and lroundf for each took about a fifth of
// `trident render --mode shaded`'s samples on Teapot (perf, 1920x1080), more than its shadow
// rays. The byte now comes from two tables made once from the formula itself (the 255 floats
// where the byte steps up, and the byte where each run of 65536 floats starts), so every byte is
// the formula's, bit for bit, for one load and one compare.
#include <cstdint>

namespace trident {

/// The formula: the reference the table is made from and tested against.
std::uint8_t gamma_byte_formula(float linear);

/// gamma_byte_formula(linear) from the tables, one load and one compare; NaN gives 0.
std::uint8_t gamma_byte(float linear);

}  // namespace trident
