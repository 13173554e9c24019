// The wide BVH's packet traversals, both node widths, compiled once for each packet width
// (accel/packet_kernels.h says why; simd/kernel_arch.h how).
#include "accel/bvh/wide_packet.h"
#include "accel/packet_kernel_instances.h"
#include "simd/kernel_arch.h"

namespace trident {

template struct PacketKernels<WideBvh<4, 4>, KernelArch>;
template struct PacketKernels<WideBvh<8, 4>, KernelArch>;
#if TRIDENT_PORTABLE_BUILD && TRIDENT_KERNEL_LANES > 4  // 4-lane packets in this file's instruction set
template struct PacketKernels<WideBvh<4, 4>, FourLanesIn<kKernelWidth>>;
template struct PacketKernels<WideBvh<8, 4>, FourLanesIn<kKernelWidth>>;
#endif

}  // namespace trident
