// The KD-tree builder's AVX-512 plane searches (sah_sweep.h) for the portable build: its baseline
// has only their scalar forms, so the 16-lane kernel file (x86-64-v4) compiles the AVX-512 ones,
// and sweep_events() and count_planes() call them when the builder found, as it started, a CPU
// that has AVX-512 and a cap that allows it. Same results bit for bit as the scalar forms (sah_sweep.h). The other widths' files hold
// nothing. Each search is inlined here (gnu::flatten), so none of its helpers is emitted out of
// line for another file to take (simd/README.md, the trap).
#include "accel/kdtree/sah_sweep.h"
#include "simd/kernel_arch.h"

namespace trident::kd {

#if TRIDENT_PORTABLE_BUILD && TRIDENT_KERNEL_LANES == 16
static_assert(TRIDENT_KD_AVX512, "the 16-lane file is compiled for x86-64-v4, which has AVX-512 F, VL, DQ and BW");

[[gnu::flatten]] SweepBest sweep_events_avx512_file(std::span<const Event> events, const SweepSetup& setup) {
    return sweep_events_avx512(events, setup);
}

[[gnu::flatten]] CountedPlane count_planes_avx512_file(const BoxEnds<8>& ends, std::size_t count,
                                                       const SweepSetup& setup) {
    return count_planes_avx512(ends, count, setup);
}
#endif

}  // namespace trident::kd
