#pragma once
// Packet widths, the xsimd architecture behind each, which of them this binary and this CPU can
// run, and dispatch_width(), which turns a width chosen at run time into a compile-time one so a
// renderer or benchmark is written once over the width (simd/README.md: per-ISA builds).
#include <array>
#include <cstddef>
#include <optional>
#include <string_view>
#include <xsimd/xsimd.hpp>

namespace trident {

/// Rays per packet: scalar is the single-ray path, the reference every packet width must match.
enum class SimdWidth { scalar, w4, w8, w16 };

inline constexpr std::array<SimdWidth, 4> kSimdWidths = {SimdWidth::scalar, SimdWidth::w4, SimdWidth::w8,
                                                         SimdWidth::w16};
/// What parse_simd_width() accepts, for help texts and error messages.
inline constexpr std::string_view kSimdWidthChoices = "auto|scalar|4|8|16";

constexpr std::size_t lane_count(SimdWidth width) {
    switch (width) {
        case SimdWidth::w4:
            return 4;
        case SimdWidth::w8:
            return 8;
        case SimdWidth::w16:
            return 16;
        case SimdWidth::scalar:
            break;
    }
    return 1;
}

/// "scalar", "4", "8" or "16": the spelling parse_simd_width() reads back.
const char* to_string(SimdWidth width);

/// One of kSimdWidthChoices; "auto" is widest_supported(). Empty for anything else. A parsed
/// width may still not be runnable here: check with is_runnable().
std::optional<SimdWidth> parse_simd_width(std::string_view text);

/// The xsimd architecture whose batch<float> has the width's lanes: SSE4.2 (blendv comes with
/// SSE4.1) for 4, AVX2 (8 x int32 for triangle ids) for 8, AVX-512BW for 16.
template <SimdWidth Width>
struct WidthArch;
template <>
struct WidthArch<SimdWidth::w4> {
    using type = xsimd::sse4_2;
};
template <>
struct WidthArch<SimdWidth::w8> {
    using type = xsimd::avx2;
};
template <>
struct WidthArch<SimdWidth::w16> {
    using type = xsimd::avx512bw;
};
template <SimdWidth Width>
using ArchOf = typename WidthArch<Width>::type;

/// Whether this binary holds kernels of that width: xsimd enables an architecture only when the
/// translation unit is compiled for it (-march=native here), so this is a compile-time fact.
constexpr bool is_compiled_in(SimdWidth width) {
    switch (width) {
        case SimdWidth::w4:
            return xsimd::sse4_2::supported();
        case SimdWidth::w8:
            return xsimd::avx2::supported();
        case SimdWidth::w16:
            return xsimd::avx512bw::supported();
        case SimdWidth::scalar:
            break;
    }
    return true;
}

/// Whether this CPU has the instruction set of that width (cpuid, through xsimd).
bool cpu_supports(SimdWidth width);

inline bool is_runnable(SimdWidth width) { return is_compiled_in(width) && cpu_supports(width); }

/// The widest width this binary can run on this CPU (scalar at worst).
SimdWidth widest_supported();

namespace detail {
[[noreturn]] void throw_width_unavailable(SimdWidth width);
}

/// Calls f.template operator()<W>() with W == width, e.g.
///     dispatch_width(width, [&]<SimdWidth W>() {
///         if constexpr (W == SimdWidth::scalar) render_rays(...);
///         else render_packets<ArchOf<W>>(...);
///     });
/// Only widths compiled into the binary are instantiated. Throws std::runtime_error, naming the
/// missing instruction set, when the width is not runnable here.
template <class F>
decltype(auto) dispatch_width(SimdWidth width, F&& f) {
    if (!is_runnable(width)) detail::throw_width_unavailable(width);
    if constexpr (is_compiled_in(SimdWidth::w16)) {
        if (width == SimdWidth::w16) return f.template operator()<SimdWidth::w16>();
    }
    if constexpr (is_compiled_in(SimdWidth::w8)) {
        if (width == SimdWidth::w8) return f.template operator()<SimdWidth::w8>();
    }
    if constexpr (is_compiled_in(SimdWidth::w4)) {
        if (width == SimdWidth::w4) return f.template operator()<SimdWidth::w4>();
    }
    return f.template operator()<SimdWidth::scalar>();
}

}  // namespace trident
