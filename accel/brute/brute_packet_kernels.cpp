// The brute force's packet traversals, compiled once for each packet width
// (accel/packet_kernels.h says why; simd/kernel_arch.h how).
#include "accel/brute/brute_force.h"
#include "accel/packet_kernel_instances.h"
#include "simd/kernel_arch.h"

namespace trident {

template struct PacketKernels<BruteForce, KernelArch>;
#if TRIDENT_PORTABLE_BUILD && TRIDENT_KERNEL_LANES > 4  // 4-lane packets in this file's instruction set
template struct PacketKernels<BruteForce, FourLanesIn<kKernelWidth>>;
#endif

}  // namespace trident
