#pragma once
// Packet widths, the xsimd architecture behind each, which of them this binary and this CPU can
// run, and dispatch_width(), which turns a width chosen at run time into a compile-time one so a
// renderer or benchmark is written once over the width (simd/README.md: per-ISA builds).
#include <array>
#include <cstddef>
#include <optional>
#include <string>
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

/// Whether this binary holds kernels of that width. CMake compiles every kernel file (the
/// structures' packet traversals and the renderer's packet loops, `*_kernels.cpp`) once per width
/// it builds, each time with that width's instruction set (simd/kernel_arch.h), and says which
/// widths it built with TRIDENT_KERNELS_W4, _W8 and _W16. The rest of the code never names a
/// batch wider than its own instruction set, so a portable build runs on any x86-64-v2 CPU.
#if !defined(TRIDENT_KERNELS_W4) || !defined(TRIDENT_KERNELS_W8) || !defined(TRIDENT_KERNELS_W16)
#error "TRIDENT_KERNELS_W4/W8/W16 come from trident_simd's compile definitions (CMakeLists.txt)"
#endif
constexpr bool is_compiled_in(SimdWidth width) {
    switch (width) {
        case SimdWidth::w4:
            return TRIDENT_KERNELS_W4;
        case SimdWidth::w8:
            return TRIDENT_KERNELS_W8;
        case SimdWidth::w16:
            return TRIDENT_KERNELS_W16;
        case SimdWidth::scalar:
            break;
    }
    return true;
}

/// Whether this translation unit may name the width's batches: its instruction set is enabled
/// here. Kernel files and tests compiled for the widest level have every width; the portable
/// build's baseline files have only the 4-lane one.
template <SimdWidth Width>
constexpr bool arch_in_this_file() {
    if constexpr (Width == SimdWidth::scalar) return true;
    else return ArchOf<Width>::supported();
}
template <SimdWidth Width>
inline constexpr bool kArchInThisFile = arch_in_this_file<Width>();

/// The instruction sets a width's kernels need, as TRIDENT_ISA names them: sse4 for 4 lanes,
/// avx2 for 8, avx512 for 16. A cap is the widest set a run may use.
enum class IsaLevel { sse4, avx2, avx512 };

/// "sse4", "avx2" or "avx512".
const char* to_string(IsaLevel level);
std::optional<IsaLevel> parse_isa_level(std::string_view text);

/// The cap on the instruction sets this process uses: TRIDENT_ISA from the environment, read at
/// the first call (std::runtime_error naming the accepted values when it holds anything else),
/// or the one set_isa_cap() gave. Empty: no cap.
std::optional<IsaLevel> isa_cap();
/// Overrides TRIDENT_ISA for the rest of the process (tests run every cap this CPU has).
void set_isa_cap(std::optional<IsaLevel> cap);

/// Whether this CPU has the instruction set of that width (cpuid, through xsimd), ignoring the cap.
bool cpu_supports(SimdWidth width);
/// Whether the cap lets a run use that width.
bool cap_allows(SimdWidth width);

inline bool is_runnable(SimdWidth width) { return is_compiled_in(width) && cpu_supports(width) && cap_allows(width); }

/// The widest width this binary can run on this CPU under the cap (scalar at worst).
SimdWidth widest_supported();

/// Why a width is not runnable: the binary, the CPU or the cap (e.g. "this CPU lacks AVX2").
std::string unavailable_reason(SimdWidth width);

namespace detail {
[[noreturn]] void throw_width_unavailable(SimdWidth width);
}

/// Calls f.template operator()<W>() with W == width, e.g.
///     dispatch_width(width, [&]<SimdWidth W>() {
///         if constexpr (W == SimdWidth::scalar) render_rays(...);
///         else TileKernels<Structure, W>::trace_primary(...);   // defined in the width's kernel file
///     });
/// Only widths compiled into the binary are instantiated; a body that names the width's batches
/// itself must also check kArchInThisFile<W>. Throws std::runtime_error, naming the
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
