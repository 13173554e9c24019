#pragma once
// The one architecture a kernel file is compiled for. CMake compiles each `*_kernels.cpp` once per
// packet width the build holds (CMakeLists.txt, trident_kernels()), defining TRIDENT_KERNEL_LANES
// to 4, 8 or 16 and targeting that width's instruction set (x86-64-v2, -v3 or -v4 in the portable
// build), so every kernel file instantiates its templates for KernelArch alone:
//     template struct PacketKernels<Bvh, KernelArch>;
// Included only by kernel files.
#include "simd/width.h"

#ifndef TRIDENT_KERNEL_LANES
#error "kernel files are compiled once per width with TRIDENT_KERNEL_LANES set (CMakeLists.txt)"
#endif

namespace trident {

inline constexpr SimdWidth kKernelWidth = TRIDENT_KERNEL_LANES == 16  ? SimdWidth::w16
                                          : TRIDENT_KERNEL_LANES == 8 ? SimdWidth::w8
                                                                      : SimdWidth::w4;
static_assert(lane_count(kKernelWidth) == TRIDENT_KERNEL_LANES, "TRIDENT_KERNEL_LANES is 4, 8 or 16");
static_assert(kArchInThisFile<kKernelWidth>, "a kernel file is compiled with its width's instruction set");

using KernelArch = ArchOf<kKernelWidth>;

}  // namespace trident
