#pragma once
// A float's bit pattern, for tests that compare results bit for bit (+0 and -0, NaN payloads).
#include <bit>
#include <cstdint>

namespace trident::testing {

inline std::uint32_t bits_of(float x) { return std::bit_cast<std::uint32_t>(x); }

}  // namespace trident::testing
