// The wide BVH's packet traversals, both widths, compiled once for every architecture built in
// (accel/packet_kernels.h says why).
#include "accel/bvh/wide_packet.h"
#include "accel/packet_kernel_instances.h"

namespace trident {

#if XSIMD_WITH_SSE4_2
template struct PacketKernels<WideBvh<4, 4>, xsimd::sse4_2>;
template struct PacketKernels<WideBvh<8, 4>, xsimd::sse4_2>;
#endif
#if XSIMD_WITH_AVX2
template struct PacketKernels<WideBvh<4, 4>, xsimd::avx2>;
template struct PacketKernels<WideBvh<8, 4>, xsimd::avx2>;
#endif
#if XSIMD_WITH_AVX512BW
template struct PacketKernels<WideBvh<4, 4>, xsimd::avx512bw>;
template struct PacketKernels<WideBvh<8, 4>, xsimd::avx512bw>;
#endif

}  // namespace trident
