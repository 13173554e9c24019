// The binary BVH's packet traversals, compiled once for every architecture built in
// (accel/packet_kernels.h says why).
#include "accel/bvh/bvh_packet.h"
#include "accel/packet_kernel_instances.h"

namespace trident {

#if XSIMD_WITH_SSE4_2
template struct PacketKernels<Bvh, xsimd::sse4_2>;
#endif
#if XSIMD_WITH_AVX2
template struct PacketKernels<Bvh, xsimd::avx2>;
#endif
#if XSIMD_WITH_AVX512BW
template struct PacketKernels<Bvh, xsimd::avx512bw>;
#endif

}  // namespace trident
