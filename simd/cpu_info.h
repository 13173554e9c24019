#pragma once
// What `trident cpu` prints: the CPU's name and the instruction sets it reports, and how this
// binary was built (its baseline and each packet width's kernels), so a user can see which
// kernels a run will choose and why.
#include <string>
#include <vector>

#include "simd/width.h"

namespace trident {

/// The CPU's brand string (cpuid leaves 0x80000002-4), "unknown" when it has none.
std::string cpu_model();

/// The instruction sets the packet widths need that this CPU reports, lowest first ("sse4.2",
/// "avx", "avx2", "fma", "avx512f", "avx512cd", "avx512dq", "avx512bw").
std::vector<std::string> cpu_features();

/// The -march the build's code outside the kernels was compiled for ("x86-64-v2" in the portable
/// build, "native" by default).
const char* baseline_march();
/// The -march of the width's kernels, or nullptr when the binary has none of that width.
const char* kernel_march(SimdWidth width);

}  // namespace trident
