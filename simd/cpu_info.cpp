#include "simd/cpu_info.h"

#include <cpuid.h>

#include <array>
#include <cstring>
#include <xsimd/xsimd.hpp>

#ifndef TRIDENT_BASELINE_MARCH_NAME
#error "TRIDENT_BASELINE_MARCH_NAME and TRIDENT_KERNEL_MARCH_NAME_4/8/16 come from CMakeLists.txt"
#endif

namespace trident {

std::string cpu_model() {
    unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
    if (__get_cpuid(0x80000000u, &eax, &ebx, &ecx, &edx) == 0 || eax < 0x80000004u) return "unknown";
    std::array<unsigned, 12> words{};
    for (unsigned leaf = 0; leaf < 3; ++leaf)
        __get_cpuid(0x80000002u + leaf, &words[4 * leaf], &words[4 * leaf + 1], &words[4 * leaf + 2],
                    &words[4 * leaf + 3]);
    char text[sizeof(words) + 1] = {};
    std::memcpy(text, words.data(), sizeof(words));
    std::string model(text);
    const auto first = model.find_first_not_of(' ');
    const auto last = model.find_last_not_of(' ');
    return first == std::string::npos ? "unknown" : model.substr(first, last - first + 1);
}

std::vector<std::string> cpu_features() {
    const auto cpu = xsimd::available_architectures();
    std::vector<std::string> out;
    const std::pair<bool, const char*> features[] = {
        {bool(cpu.sse4_2), "sse4.2"},     {bool(cpu.avx), "avx"},           {bool(cpu.avx2), "avx2"},
        {bool(cpu.fma3_avx2), "fma"},     {bool(cpu.avx512f), "avx512f"},   {bool(cpu.avx512cd), "avx512cd"},
        {bool(cpu.avx512dq), "avx512dq"}, {bool(cpu.avx512bw), "avx512bw"},
    };
    for (const auto& [present, name] : features)
        if (present) out.emplace_back(name);
    return out;
}

const char* baseline_march() { return TRIDENT_BASELINE_MARCH_NAME; }

const char* kernel_march(SimdWidth width) {
    if (!is_compiled_in(width)) return nullptr;
    switch (width) {
        case SimdWidth::w4:
            return TRIDENT_KERNEL_MARCH_NAME_4;
        case SimdWidth::w8:
            return TRIDENT_KERNEL_MARCH_NAME_8;
        case SimdWidth::w16:
            return TRIDENT_KERNEL_MARCH_NAME_16;
        case SimdWidth::scalar:
            break;
    }
    return TRIDENT_BASELINE_MARCH_NAME;
}

}  // namespace trident
