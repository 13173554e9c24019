#pragma once
// The one architecture a kernel file is compiled for. CMake compiles each `*_kernels.cpp` once per
// packet width the build holds (CMakeLists.txt, trident_kernels()), defining TRIDENT_KERNEL_LANES
// to 4, 8 or 16 and targeting that width's instruction set (x86-64-v2, -v3 or -v4 in the portable
// build), so every kernel file instantiates its templates for KernelArch alone:
//     template struct PacketKernels<Bvh, KernelArch>;
// and, in the portable build's 8- and 16-lane files, for the narrower widths' LanesIn too.
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

/// `Width`'s batches (SSE4.2's 4 lanes, AVX2's 8) in the instruction set of the kernel file of
/// the wider width `File`: the portable build (TRIDENT_PORTABLE_BUILD) runs 4- and 8-lane packets
/// in the widest file the CPU has, with its encodings (three-operand VEX where the 4-lane file has
/// SSE's two-operand forms; EVEX and 32 registers in the AVX-512 file), render/render_kernels.h.
/// The kernels are xsimd's of `Width`'s own architecture, reached through the base class, and
/// round as they do (no FMA: -ffp-contract=off, none written); only the encoding differs. A type
/// of its own per width and file, so that every template over it is that file's own symbol and no
/// other file can be given its copy (simd/README.md, the trap).
template <SimdWidth Width, SimdWidth File>
struct LanesIn : ArchOf<Width> {
    static_assert(lane_count(Width) < lane_count(File), "a file's own width is KernelArch");
    static constexpr bool supported() noexcept { return ArchOf<File>::supported(); }
    static constexpr bool available() noexcept { return true; }
    static constexpr unsigned version() noexcept { return ArchOf<Width>::version(); }
    static constexpr char const* name() noexcept { return "narrower lanes in a wider file"; }
};

/// Whether this file holds the 4- and the 8-lane packets too (the portable build's wider files).
#define TRIDENT_FILE_HOLDS_W4 (TRIDENT_PORTABLE_BUILD && TRIDENT_KERNEL_LANES > 4)
#define TRIDENT_FILE_HOLDS_W8 (TRIDENT_PORTABLE_BUILD && TRIDENT_KERNEL_LANES > 8)

/// The architecture of a width's packets in this file: the file's own, or the narrower width's
/// lanes in its instruction set.
template <SimdWidth Width>
using PacketArchInFile = std::conditional_t<Width == kKernelWidth, KernelArch, LanesIn<Width, kKernelWidth>>;

}  // namespace trident

namespace xsimd::types {

/// LanesIn's batches hold the registers of its width's architecture (xsimd's
/// XSIMD_DECLARE_SIMD_REGISTER_ALIAS, for a family of architectures). Neither base has mask
/// registers, so its batch_bool is a vector, as theirs are.
template <class T, trident::SimdWidth Width, trident::SimdWidth File>
struct simd_register<T, trident::LanesIn<Width, File>> : simd_register<T, trident::ArchOf<Width>> {
    using register_type = typename simd_register<T, trident::ArchOf<Width>>::register_type;
    simd_register(register_type reg) noexcept : simd_register<T, trident::ArchOf<Width>>{reg} {}
    simd_register() = default;
};
template <class T, trident::SimdWidth Width, trident::SimdWidth File>
struct has_simd_register<T, trident::LanesIn<Width, File>> : has_simd_register<T, trident::ArchOf<Width>> {};

}  // namespace xsimd::types
