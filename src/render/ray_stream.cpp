#include "render/ray_stream.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <type_traits>

#include "core/traversal_variant.h"
#include "render/render_kernels.h"

namespace trident {
namespace {

/// Writes one result per ray: the any-hit bit or the closest hit.
template <bool AnyHit>
using Result = std::conditional_t<AnyHit, std::uint8_t, Hit>;

/// The rays of a stream as the kernels below read them: a list of Rays, results in list order.
struct RayList {
    std::span<const Ray> rays;
    std::size_t size() const { return rays.size(); }
    const Ray& ray(std::size_t i) const { return rays[i]; }
    std::size_t out_index(std::size_t i) const { return i; }
};

/// Rays gathered through `order` from arrays, results scattered back through it; every ray is
/// traced (the caller checked them), and packets take consecutive entries of `order`.
struct GatheredRays {
    const StridedRays& arrays;
    std::span<const std::size_t> order;
    std::size_t size() const { return order.size(); }
    Ray ray(std::size_t i) const { return arrays.ray(order[i]); }
    std::size_t out_index(std::size_t i) const { return order[i]; }
};

template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Structure, class Rays>
void trace_single(const Structure& structure, const Rays& rays, std::span<Result<AnyHit>> out) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
        NoCounters counters;
        const Ray ray = rays.ray(i);
        Result<AnyHit>& result = out[rays.out_index(i)];
        if constexpr (AnyHit)
            result = is_traced(ray) && structure.template occluded<Test, Slabs>(ray, counters);
        else
            result = is_traced(ray) ? structure.template intersect<Test, Slabs>(ray, counters) : Hit{};
    }
}

/// One packet of the rays at `index` (at most the width's lanes), its results written to `out`,
/// traced in the kernel file of width `File`.
template <bool AnyHit, SimdWidth Width, SimdWidth File, class Structure, class Rays>
void trace_packet(const Structure& structure, const Rays& rays, std::span<const std::size_t> index,
                  std::span<Result<AnyHit>> out, PacketVariant variant) {
    using Kernels = RenderKernels<Structure, Width, File>;
    std::array<Ray, Kernels::kLanes> lane_rays;
    for (std::size_t k = 0; k < index.size(); ++k) lane_rays[k] = rays.ray(index[k]);
    const std::span<const Ray> packet(lane_rays.data(), index.size());
    if constexpr (AnyHit) {
        const std::uint32_t bits = Kernels::occlude_rays(structure, packet, variant);
        for (std::size_t k = 0; k < index.size(); ++k) out[rays.out_index(index[k])] = (bits >> k) & 1u;
    } else {
        std::array<Hit, Kernels::kLanes> lane_hits;
        Kernels::intersect_rays(structure, packet, std::span<Hit>(lane_hits.data(), index.size()), variant);
        for (std::size_t k = 0; k < index.size(); ++k) out[rays.out_index(index[k])] = lane_hits[k];
    }
}

template <bool AnyHit, SimdWidth Width, SimdWidth File, class Structure>
void trace_packets(const Structure& structure, const RayList& rays, std::span<Result<AnyHit>> out,
                   PacketGrouping grouping, PacketVariant variant) {
    for (std::size_t i = 0; i < rays.size(); ++i)
        if (!is_traced(rays.ray(i))) out[i] = Result<AnyHit>{};
    for_each_stream_packet(rays.rays, lane_count(Width), grouping, [&](std::span<const std::size_t> index) {
        trace_packet<AnyHit, Width, File>(structure, rays, index, out, variant);
    });
}

template <bool AnyHit, SimdWidth Width, SimdWidth File, class Structure>
void trace_packets(const Structure& structure, const GatheredRays& rays, std::span<Result<AnyHit>> out,
                   PacketGrouping, PacketVariant variant) {
    constexpr std::size_t kLanes = lane_count(Width);
    std::array<std::size_t, kLanes> index;
    for (std::size_t first = 0; first < rays.size(); first += kLanes) {
        const std::size_t lanes = std::min(kLanes, rays.size() - first);
        for (std::size_t k = 0; k < lanes; ++k) index[k] = first + k;
        trace_packet<AnyHit, Width, File>(structure, rays, std::span<const std::size_t>(index.data(), lanes), out,
                                          variant);
    }
}

template <bool AnyHit, class Rays>
void trace_stream(const AnyAccel& accel, const Rays& rays, std::span<Result<AnyHit>> out, StreamTraversal traversal,
                  TriangleTest test) {
    // Single rays take the variant as template arguments; the packet kernels take it at run time.
    if (traversal.width == SimdWidth::scalar) {
        // The portable build's single rays of a list run in the widest kernel file the CPU (and the
        // cap) allow; gathered rays stay at the baseline.
        if constexpr (std::is_same_v<Rays, RayList>) {
            const bool in_kernel_file = in_widest_kernel_file([&]<SimdWidth File>() {
                accel.visit([&](const auto& structure) {
                    using FileKernels = SingleRayKernels<std::decay_t<decltype(structure)>, File>;
                    if constexpr (AnyHit)
                        FileKernels::occlude_rays(structure, rays.rays, out, test, traversal.slabs);
                    else
                        FileKernels::intersect_rays(structure, rays.rays, out, test, traversal.slabs);
                });
            });
            if (in_kernel_file) return;
        }
        with_traversal_variant(test, traversal.slabs, [&](auto test_tag, auto slabs_tag) {
            accel.visit([&](const auto& structure) {
                trace_single<AnyHit, decltype(test_tag)::value, decltype(slabs_tag)::value>(structure, rays, out);
            });
        });
        return;
    }
    const PacketVariant variant{.test = test, .slabs = traversal.slabs};
    accel.visit([&](const auto& structure) {
        // In the portable build, in the widest kernel file the CPU (and the cap) allow.
        dispatch_packet_width(traversal.width, [&]<SimdWidth W, SimdWidth File>() {
            trace_packets<AnyHit, W, File>(structure, rays, out, traversal.grouping, variant);
        });
    });
}

template <bool AnyHit>
void trace_stream_parallel(const AnyAccel& accel, std::span<const Ray> rays, std::span<Result<AnyHit>> out,
                           StreamTraversal traversal, TriangleTest test) {
    if (out.size() != rays.size()) throw std::invalid_argument("trace stream: one result per ray is needed");
    for_each_stream_chunk(rays.size(), [&](std::size_t first, std::size_t last) {
        trace_stream<AnyHit>(accel, RayList{rays.subspan(first, last - first)}, out.subspan(first, last - first),
                             traversal, test);
    });
}

}  // namespace

void occlude_stream(const AnyAccel& accel, std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                    StreamTraversal traversal, TriangleTest test) {
    if (occluded.size() != rays.size()) throw std::invalid_argument("trace stream: one result per ray is needed");
    trace_stream<true>(accel, RayList{rays}, occluded, traversal, test);
}

void intersect_stream(const AnyAccel& accel, std::span<const Ray> rays, std::span<Hit> hits, StreamTraversal traversal,
                      TriangleTest test) {
    if (hits.size() != rays.size()) throw std::invalid_argument("trace stream: one result per ray is needed");
    trace_stream<false>(accel, RayList{rays}, hits, traversal, test);
}

void occlude_stream(const AnyAccel& accel, const StridedRays& rays, std::span<const std::size_t> order,
                    std::span<std::uint8_t> occluded, StreamTraversal traversal, TriangleTest test) {
    trace_stream<true>(accel, GatheredRays{rays, order}, occluded, traversal, test);
}

void intersect_stream(const AnyAccel& accel, const StridedRays& rays, std::span<const std::size_t> order,
                      std::span<Hit> hits, StreamTraversal traversal, TriangleTest test) {
    trace_stream<false>(accel, GatheredRays{rays, order}, hits, traversal, test);
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
