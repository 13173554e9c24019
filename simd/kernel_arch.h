#pragma once
// The one architecture a kernel file is compiled for. CMake compiles each `*_kernels.cpp` once per
// packet width the build holds (CMakeLists.txt, trident_kernels()), defining TRIDENT_KERNEL_LANES
// to 4, 8 or 16 and targeting that width's instruction set (x86-64-v2, -v3 or -v4 in the portable
// build), so every kernel file instantiates its templates for KernelArch alone:
//     template struct PacketKernels<Bvh, KernelArch>;
// and, in the portable build's 8- and 16-lane files, for FourLanesIn<kKernelWidth> too.
// Included only by kernel files.
#include <type_traits>
#include <xsimd/xsimd.hpp>

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

/// SSE4.2's 4-lane batches in the instruction set of the kernel file of width `File`: the
/// portable build (TRIDENT_PORTABLE_BUILD) runs 4-lane packets in its AVX2 and AVX-512 files on
/// a CPU that has them, with three-operand VEX or EVEX encodings where the 4-lane file has SSE's
/// two-operand forms (render/render_kernels.h). The kernels are xsimd's SSE4.2 ones, reached
/// through the base class, and round as they do (no FMA: -ffp-contract=off, none written); only
/// the encoding differs. A type of its own per file, so that every template over it is that
/// file's own symbol and no other file can be given its copy (simd/README.md, the trap).
template <SimdWidth File>
struct FourLanesIn : xsimd::sse4_2 {
    static constexpr bool supported() noexcept { return ArchOf<File>::supported(); }
    static constexpr bool available() noexcept { return true; }
    static constexpr unsigned version() noexcept { return xsimd::sse4_2::version(); }
    static constexpr char const* name() noexcept { return "sse4.2 lanes in a wider file"; }
};

/// The architecture of a width's packets in this file: the file's own, or 4 lanes in its
/// instruction set.
template <SimdWidth Width>
using PacketArchInFile = std::conditional_t<Width == kKernelWidth, KernelArch, FourLanesIn<kKernelWidth>>;

}  // namespace trident

namespace xsimd::types {

/// FourLanesIn's batches hold SSE's registers (xsimd's XSIMD_DECLARE_SIMD_REGISTER_ALIAS, for a
/// family of architectures).
template <class T, trident::SimdWidth File>
struct simd_register<T, trident::FourLanesIn<File>> : simd_register<T, sse4_2> {
    using register_type = typename simd_register<T, sse4_2>::register_type;
    simd_register(register_type reg) noexcept : simd_register<T, sse4_2>{reg} {}
    simd_register() = default;
};
template <class T, trident::SimdWidth File>
struct has_simd_register<T, trident::FourLanesIn<File>> : has_simd_register<T, sse4_2> {};

}  // namespace xsimd::types
