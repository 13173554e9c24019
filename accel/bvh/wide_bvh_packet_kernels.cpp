// The wide BVH's packet traversals, every node width, compiled once for each packet width
// (accel/packet_kernels.h says why; simd/kernel_arch.h how).
#include "accel/bvh/wide_packet.h"
#include "accel/packet_kernel_instances.h"
#include "simd/kernel_arch.h"

namespace trident {

template struct PacketKernels<WideBvh<4, 4>, KernelArch>;
template struct PacketKernels<WideBvh<8, 4>, KernelArch>;
template struct PacketKernels<WideBvh<16, 4>, KernelArch>;
#if TRIDENT_FILE_HOLDS_W4  // the narrower packets in this file's instruction set
template struct PacketKernels<WideBvh<4, 4>, LanesIn<SimdWidth::w4, kKernelWidth>>;
template struct PacketKernels<WideBvh<8, 4>, LanesIn<SimdWidth::w4, kKernelWidth>>;
template struct PacketKernels<WideBvh<16, 4>, LanesIn<SimdWidth::w4, kKernelWidth>>;
#endif
#if TRIDENT_FILE_HOLDS_W8
template struct PacketKernels<WideBvh<4, 4>, LanesIn<SimdWidth::w8, kKernelWidth>>;
template struct PacketKernels<WideBvh<8, 4>, LanesIn<SimdWidth::w8, kKernelWidth>>;
template struct PacketKernels<WideBvh<16, 4>, LanesIn<SimdWidth::w8, kKernelWidth>>;
#endif

}  // namespace trident
