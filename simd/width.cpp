#include "simd/width.h"

#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>

namespace trident {

namespace {

const char* instruction_set(SimdWidth width) {
    switch (width) {
        case SimdWidth::w4:
            return "SSE4.2";
        case SimdWidth::w8:
            return "AVX2";
        case SimdWidth::w16:
            return "AVX-512 (F, CD, DQ, BW)";
        case SimdWidth::scalar:
            break;
    }
    return "none";
}

IsaLevel level_of(SimdWidth width) {
    switch (width) {
        case SimdWidth::w16:
            return IsaLevel::avx512;
        case SimdWidth::w8:
            return IsaLevel::avx2;
        case SimdWidth::w4:
        case SimdWidth::scalar:
            break;
    }
    return IsaLevel::sse4;
}

constexpr std::array<IsaLevel, 3> kIsaLevels = {IsaLevel::sse4, IsaLevel::avx2, IsaLevel::avx512};

/// The cap: read from TRIDENT_ISA once, unless set_isa_cap() came first.
struct CapState {
    std::once_flag read;
    std::optional<IsaLevel> cap;
};
CapState& cap_state() {
    static CapState state;
    return state;
}

std::optional<IsaLevel> read_isa_environment() {
    const char* text = std::getenv("TRIDENT_ISA");
    if (text == nullptr || *text == '\0') return std::nullopt;
    if (const auto level = parse_isa_level(text)) return level;
    throw std::runtime_error(std::string("TRIDENT_ISA=") + text + ": expected sse4, avx2 or avx512");
}

}  // namespace

const char* to_string(IsaLevel level) {
    switch (level) {
        case IsaLevel::avx2:
            return "avx2";
        case IsaLevel::avx512:
            return "avx512";
        case IsaLevel::sse4:
            break;
    }
    return "sse4";
}

std::optional<IsaLevel> parse_isa_level(std::string_view text) {
    for (const IsaLevel level : kIsaLevels)
        if (text == to_string(level)) return level;
    return std::nullopt;
}

std::optional<IsaLevel> isa_cap() {
    CapState& state = cap_state();
    std::call_once(state.read, [&] { state.cap = read_isa_environment(); });
    return state.cap;
}

void set_isa_cap(std::optional<IsaLevel> cap) {
    CapState& state = cap_state();
    std::call_once(state.read, [] {});
    state.cap = cap;
}

bool cap_allows(SimdWidth width) {
    const auto cap = isa_cap();
    return width == SimdWidth::scalar || !cap || level_of(width) <= *cap;
}

const char* to_string(SimdWidth width) {
    switch (width) {
        case SimdWidth::w4:
            return "4";
        case SimdWidth::w8:
            return "8";
        case SimdWidth::w16:
            return "16";
        case SimdWidth::scalar:
            break;
    }
    return "scalar";
}

std::optional<SimdWidth> parse_simd_width(std::string_view text) {
    if (text == "auto") return widest_supported();
    for (const SimdWidth width : kSimdWidths)
        if (text == to_string(width)) return width;
    return std::nullopt;
}

bool cpu_supports(SimdWidth width) {
    // xsimd 8.1 reads cpuid only and does not ask the OS (XGETBV) whether it saves the wide
    // registers; Linux has done so since those CPUs appeared.
    const auto cpu = xsimd::available_architectures();
    switch (width) {
        case SimdWidth::w4:
            return cpu.sse4_2;
        case SimdWidth::w8:
            return cpu.avx2;
        case SimdWidth::w16:
            return cpu.avx512f && cpu.avx512cd && cpu.avx512dq && cpu.avx512bw;
        case SimdWidth::scalar:
            break;
    }
    return true;
}

SimdWidth widest_supported() {
    for (const SimdWidth width : {SimdWidth::w16, SimdWidth::w8, SimdWidth::w4})
        if (is_runnable(width)) return width;
    return SimdWidth::scalar;
}

std::string unavailable_reason(SimdWidth width) {
    if (!is_compiled_in(width)) return std::string("this binary was built without ") + instruction_set(width) + " kernels";
    if (!cpu_supports(width)) return std::string("this CPU lacks ") + instruction_set(width);
    if (!cap_allows(width))
        return std::string("TRIDENT_ISA=") + to_string(*isa_cap()) + " caps the instruction sets below " +
               instruction_set(width);
    return "it is available";
}

namespace detail {

void throw_width_unavailable(SimdWidth width) {
    const std::string why = unavailable_reason(width);
    throw std::runtime_error(std::string("SIMD width ") + to_string(width) + " is not available: " + why);
}

}  // namespace detail

}  // namespace trident
