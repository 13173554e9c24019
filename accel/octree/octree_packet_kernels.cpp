// The octree's packet traversals, compiled once for each packet width
// (accel/packet_kernels.h says why; simd/kernel_arch.h how).
#include "accel/octree/octree_packet.h"
#include "accel/packet_kernel_instances.h"
#include "simd/kernel_arch.h"

namespace trident {

template struct PacketKernels<Octree, KernelArch>;

}  // namespace trident
