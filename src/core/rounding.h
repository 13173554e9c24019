#pragma once
// Bounds on floating-point rounding error, for the tests that must stay conservative under it.
#include <limits>

namespace trident {

/// gamma(n) = n u / (1 - n u), the bound on the relative error of n roundings (u = 2^-24; Higham,
/// "Accuracy and Stability of Numerical Algorithms", section 3.1, as used by Ize and pbrt).
constexpr float rounding_gamma(int n) {
    constexpr float u = std::numeric_limits<float>::epsilon() * 0.5f;
    return (float(n) * u) / (1.0f - float(n) * u);
}

}  // namespace trident
