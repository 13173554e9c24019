#pragma once
// The traversal column of the benchmark: one ray at a time (`scalar`) or packets of 4, 8 or 16
// rays over SIMD lanes (simd/width.h), traced by trace_primary() as 2x2, 4x2 or 4x4 pixel blocks.
#include <optional>
#include <string_view>

#include "simd/width.h"

namespace trident::bench {

enum class Traversal { scalar, simd4, simd8, simd16 };

inline constexpr Traversal kAllTraversals[] = {Traversal::scalar, Traversal::simd4, Traversal::simd8,
                                               Traversal::simd16};

constexpr const char* to_string(Traversal traversal) {
    switch (traversal) {
        case Traversal::scalar:
            return "scalar";
        case Traversal::simd4:
            return "simd4";
        case Traversal::simd8:
            return "simd8";
        case Traversal::simd16:
            return "simd16";
    }
    return "?";
}

constexpr SimdWidth simd_width(Traversal traversal) {
    switch (traversal) {
        case Traversal::scalar:
            return SimdWidth::scalar;
        case Traversal::simd4:
            return SimdWidth::w4;
        case Traversal::simd8:
            return SimdWidth::w8;
        case Traversal::simd16:
            return SimdWidth::w16;
    }
    return SimdWidth::scalar;
}

/// Rays traced together: 1 for scalar, the packet width otherwise.
constexpr int rays_per_call(Traversal traversal) { return int(lane_count(simd_width(traversal))); }

/// The instruction set a packet width needs, for messages.
constexpr const char* instruction_set(Traversal traversal) {
    switch (traversal) {
        case Traversal::simd4:
            return "SSE4.2";
        case Traversal::simd8:
            return "AVX2";
        case Traversal::simd16:
            return "AVX-512BW";
        case Traversal::scalar:
            break;
    }
    return "none";
}

/// Accepts the names above and the trident CLI's spellings: 4, 8, 16, and auto (the widest this
/// binary can run on this CPU).
inline std::optional<Traversal> parse_traversal(std::string_view name) {
    for (Traversal traversal : kAllTraversals) {
        const std::string_view full = to_string(traversal);
        if (name == full || (full.starts_with("simd") && name == full.substr(4))) return traversal;
        if (name == "auto" && simd_width(traversal) == widest_supported()) return traversal;
    }
    return std::nullopt;
}

/// Whether this binary holds the width's kernels and this CPU can run them (scalar always).
inline bool is_runnable(Traversal traversal) { return trident::is_runnable(simd_width(traversal)); }

}  // namespace trident::bench
