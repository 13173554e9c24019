// The binary BVH's packet traversals, compiled once for each packet width
// (accel/packet_kernels.h says why; simd/kernel_arch.h how).
#include "accel/bvh/bvh_packet.h"
#include "accel/packet_kernel_instances.h"
#include "simd/kernel_arch.h"

namespace trident {

template struct PacketKernels<Bvh, KernelArch>;
#if TRIDENT_PORTABLE_BUILD && TRIDENT_KERNEL_LANES > 4  // 4-lane packets in this file's instruction set
template struct PacketKernels<Bvh, FourLanesIn<kKernelWidth>>;
#endif

}  // namespace trident
