#include "simd/width.h"

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

}  // namespace

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

namespace detail {

void throw_width_unavailable(SimdWidth width) {
    const std::string why = is_compiled_in(width)
                                ? std::string("this CPU lacks ") + instruction_set(width)
                                : std::string("this binary was built without ") + instruction_set(width) + " kernels";
    throw std::runtime_error(std::string("SIMD width ") + to_string(width) + " is not available: " + why);
}

}  // namespace detail

}  // namespace trident
