#include "render/ray_stream.h"

#include <algorithm>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "core/traversal_variant.h"
#include "render/occlude_in_order.h"
#include "render/render_kernels.h"

namespace trident {
namespace {

/// Writes one result per ray: the any-hit bit or the closest hit.
template <bool AnyHit>
using Result = std::conditional_t<AnyHit, std::uint8_t, Hit>;

/// The rays one at a time (untraceable ones get no hit, not occluded), in the widest kernel file
/// the CPU (and the cap) allow in the portable build, else in the baseline's.
template <bool AnyHit, class Structure>
void trace_single_rays(const Structure& structure, std::span<const Ray> rays, std::span<Result<AnyHit>> out,
                       TriangleTest test, SlabTest slabs, RayCoherence coherence, bool last_occluder) {
    const bool in_kernel_file = in_widest_kernel_file([&]<SimdWidth File>() {
        using FileKernels = SingleRayKernels<Structure, File>;
        if constexpr (AnyHit)
            FileKernels::occlude_rays(structure, rays, out, test, slabs, last_occluder);
        else
            FileKernels::intersect_rays(structure, rays, out, test, slabs, coherence);
    });
    if (in_kernel_file) return;
    with_traversal_variant(test, slabs, [&](auto test_tag, auto slabs_tag) {
        constexpr TriangleTest kTest = decltype(test_tag)::value;
        constexpr SlabTest kSlabs = decltype(slabs_tag)::value;
        if constexpr (AnyHit) {
            occlude_in_order<kTest, kSlabs>(structure, rays, out, last_occluder);
        } else {
            for (std::size_t i = 0; i < rays.size(); ++i) {
                NoCounters counters;
                out[i] = is_traced(rays[i]) ? intersect_hinted<kTest, kSlabs>(structure, rays[i], counters, coherence)
                                            : Hit{};
            }
        }
    });
}

/// The rays cut into packets as `grouping` says, each traced by the packet walk in the kernel file
/// of width `File` (RenderKernels' stream loop), except those whose lanes would all walk alone
/// from the root (the wide BVH's incoherent packets over a large tree): these are only marked,
/// from the rays where they lie, and traced afterwards as the single rays they would become, run
/// by run in list order. Building such a packet, taking it apart and scattering its hits cost
/// Bunny's diffuse rays 9% over the single rays' time, and gathering its rays to ask another 4%
/// (perf, bench/experiments/bvh-traversal.md). Every ray's result is the same in any order.
template <bool AnyHit, SimdWidth Width, SimdWidth File, class Structure>
void trace_packets(const Structure& structure, std::span<const Ray> rays, std::span<Result<AnyHit>> out,
                   PacketGrouping grouping, PacketVariant variant, bool last_occluder) {
    for (std::size_t i = 0; i < rays.size(); ++i)
        if (!is_traced(rays[i])) out[i] = Result<AnyHit>{};
    // 1 where a ray's packet goes alone. Untraced rays between such rays join their run: their
    // results are already written, and the single-ray loop skips them. One buffer per thread,
    // reused from chunk to chunk of the stream rather than allocated for each; left empty for a
    // structure whose packets never go alone.
    thread_local std::vector<std::uint8_t> alone;
    if constexpr (WalksLanesAlone<Structure>)
        alone.assign(rays.size(), 0);
    else
        alone.clear();
    using Kernels = RenderKernels<Structure, Width, File>;
    bool any_alone;
    if constexpr (AnyHit)
        any_alone = Kernels::occlude_stream(structure, rays, out, grouping, variant, last_occluder, alone);
    else
        any_alone = Kernels::intersect_stream(structure, rays, out, grouping, variant, alone);
    if (!any_alone) return;
    for (std::size_t i = 0; i < rays.size();) {
        if (!alone[i]) {
            ++i;
            continue;
        }
        std::size_t end = i + 1;
        while (end < rays.size() && (alone[end] || !is_traced(rays[end]))) ++end;
        trace_single_rays<AnyHit>(structure, rays.subspan(i, end - i), out.subspan(i, end - i), variant.test,
                                  variant.slabs, RayCoherence::incoherent, last_occluder);
        i = end;
    }
}

template <bool AnyHit>
void trace_stream(const AnyAccel& accel, std::span<const Ray> rays, std::span<Result<AnyHit>> out,
                  StreamTraversal traversal, TriangleTest test) {
    // Single rays take the variant as template arguments; the packet kernels take it at run time.
    if (traversal.width == SimdWidth::scalar || stream_walks_rays_alone(accel, traversal)) {
        accel.visit([&](const auto& structure) {
            trace_single_rays<AnyHit>(structure, rays, out, test, traversal.slabs, traversal.coherence,
                                      traversal.last_occluder);
        });
        return;
    }
    const PacketVariant variant{.test = test, .slabs = traversal.slabs};
    accel.visit([&](const auto& structure) {
        // In the portable build, in the widest kernel file the CPU (and the cap) allow.
        dispatch_packet_width(traversal.width, [&]<SimdWidth W, SimdWidth File>() {
            trace_packets<AnyHit, W, File>(structure, rays, out, traversal.grouping, variant, traversal.last_occluder);
        });
    });
}

template <bool AnyHit>
bool trace_array_tile(const AnyAccel& accel, const RayImage& image, const ImageTile& tile, Result<AnyHit>* out,
                      StreamTraversal traversal, TriangleTest test) {
    bool traced = false;
    if (traversal.width == SimdWidth::scalar) {
        // As the renderer's single rays: in the widest kernel file the CPU (and the cap) allow.
        const bool in_kernel_file = in_widest_kernel_file([&]<SimdWidth File>() {
            accel.visit([&](const auto& structure) {
                using FileKernels = SingleRayKernels<std::decay_t<decltype(structure)>, File>;
                if constexpr (AnyHit)
                    traced = FileKernels::occlude_array_tile(structure, image, tile, out, test, traversal.slabs);
                else
                    traced = FileKernels::intersect_array_tile(structure, image, tile, out, test, traversal.slabs);
            });
        });
        if (in_kernel_file) return traced;
        accel.visit([&](const auto& structure) {
            traced = trace_array_tile_singly<AnyHit>(structure, image, tile, out, test, traversal.slabs);
        });
        return traced;
    }
    const PacketVariant variant{.test = test, .slabs = traversal.slabs};
    accel.visit([&](const auto& structure) {
        dispatch_packet_width(traversal.width, [&]<SimdWidth W, SimdWidth File>() {
            using Kernels = RenderKernels<std::decay_t<decltype(structure)>, W, File>;
            if constexpr (AnyHit)
                traced = Kernels::occlude_array_tile(structure, image, tile, out, variant);
            else
                traced = Kernels::intersect_array_tile(structure, image, tile, out, variant);
        });
    });
    return traced;
}

template <bool AnyHit>
void trace_stream_parallel(const AnyAccel& accel, std::span<const Ray> rays, std::span<Result<AnyHit>> out,
                           StreamTraversal traversal, TriangleTest test) {
    if (out.size() != rays.size()) throw std::invalid_argument("trace stream: one result per ray is needed");
    for_each_stream_chunk(rays.size(), [&](std::size_t first, std::size_t last) {
        trace_stream<AnyHit>(accel, rays.subspan(first, last - first), out.subspan(first, last - first), traversal,
                             test);
    });
}

}  // namespace

bool stream_walks_rays_alone(const AnyAccel& accel, const StreamTraversal& traversal) {
    if (traversal.width == SimdWidth::scalar || traversal.coherence != RayCoherence::incoherent) return false;
    return accel.visit([](const auto& structure) {
        if constexpr (WalksLanesAlone<std::decay_t<decltype(structure)>>)
            return structure.incoherent_packets_walk_alone();
        else
            return false;
    });
}

void occlude_stream(const AnyAccel& accel, std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                    StreamTraversal traversal, TriangleTest test) {
    if (occluded.size() != rays.size()) throw std::invalid_argument("trace stream: one result per ray is needed");
    trace_stream<true>(accel, rays, occluded, traversal, test);
}

void intersect_stream(const AnyAccel& accel, std::span<const Ray> rays, std::span<Hit> hits, StreamTraversal traversal,
                      TriangleTest test) {
    if (hits.size() != rays.size()) throw std::invalid_argument("trace stream: one result per ray is needed");
    trace_stream<false>(accel, rays, hits, traversal, test);
}

bool occlude_array_tile(const AnyAccel& accel, const RayImage& image, const ImageTile& tile, std::uint8_t* out,
                        StreamTraversal traversal, TriangleTest test) {
    return trace_array_tile<true>(accel, image, tile, out, traversal, test);
}

bool intersect_array_tile(const AnyAccel& accel, const RayImage& image, const ImageTile& tile, Hit* out,
                          StreamTraversal traversal, TriangleTest test) {
    return trace_array_tile<false>(accel, image, tile, out, traversal, test);
}

void occlude_stream_parallel(const AnyAccel& accel, std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                             StreamTraversal traversal, TriangleTest test) {
    trace_stream_parallel<true>(accel, rays, occluded, traversal, test);
}

void intersect_stream_parallel(const AnyAccel& accel, std::span<const Ray> rays, std::span<Hit> hits,
                               StreamTraversal traversal, TriangleTest test) {
    trace_stream_parallel<false>(accel, rays, hits, traversal, test);
}

}  // namespace trident
