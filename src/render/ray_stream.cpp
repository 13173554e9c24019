#include "render/ray_stream.h"

#include <fmt/format.h>

#include <array>
#include <stdexcept>
#include <type_traits>

#include "render/trace.h"
#include "simd/packet.h"

namespace trident {
namespace {

/// Writes one result per ray: the any-hit bit or the closest hit.
template <bool AnyHit>
using Result = std::conditional_t<AnyHit, std::uint8_t, Hit>;

template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Structure>
void trace_single(const Structure& structure, std::span<const Ray> rays, std::span<Result<AnyHit>> out) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
        NoCounters counters;
        if constexpr (AnyHit)
            out[i] = is_traced(rays[i]) && structure.template occluded<Test, Slabs>(rays[i], counters);
        else
            out[i] = is_traced(rays[i]) ? structure.template intersect<Test, Slabs>(rays[i], counters) : Hit{};
    }
}

template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Arch, class Structure>
void trace_packets(const Structure& structure, std::span<const Ray> rays, std::span<Result<AnyHit>> out,
                   PacketGrouping grouping) {
    constexpr std::size_t kLanes = RayPacket<Arch>::width;
    for (std::size_t i = 0; i < rays.size(); ++i)
        if (!is_traced(rays[i])) out[i] = Result<AnyHit>{};
    for_each_stream_packet(rays, kLanes, grouping, [&](std::span<const std::size_t> index) {
        std::array<Ray, kLanes> lane_rays;
        for (std::size_t k = 0; k < index.size(); ++k) lane_rays[k] = rays[index[k]];
        const RayPacket<Arch> packet(std::span<const Ray>(lane_rays.data(), index.size()));
        NoCounters counters;
        if constexpr (AnyHit) {
            const std::uint32_t bits = simd::mask_bits(structure.template occluded<Test, Slabs>(packet, counters));
            for (std::size_t k = 0; k < index.size(); ++k) out[index[k]] = (bits >> k) & 1u;
        } else {
            HitPacket<Arch> hits(packet);
            structure.template intersect<Test, Slabs>(packet, hits, counters);
            std::array<Hit, kLanes> lane_hits;
            hits.store(std::span<Hit>(lane_hits.data(), index.size()));
            for (std::size_t k = 0; k < index.size(); ++k) out[index[k]] = lane_hits[k];
        }
    });
}

template <bool AnyHit>
void trace_stream(const AnyAccel& accel, std::span<const Ray> rays, std::span<Result<AnyHit>> out,
                  StreamTraversal traversal, TriangleTest test) {
    if (out.size() != rays.size()) throw std::invalid_argument("trace stream: one result per ray is needed");
    with_traversal_variant(test, traversal.slabs, [&](auto test_tag, auto slabs_tag) {
        constexpr TriangleTest Test = decltype(test_tag)::value;
        constexpr SlabTest Slabs = decltype(slabs_tag)::value;
        accel.visit([&](const auto& structure) {
            using Structure = std::decay_t<decltype(structure)>;
            dispatch_width(traversal.width, [&]<SimdWidth W>() {
                if constexpr (W == SimdWidth::scalar)
                    trace_single<AnyHit, Test, Slabs>(structure, rays, out);
                else if constexpr (PacketTraversable<Structure, ArchOf<W>>)
                    trace_packets<AnyHit, Test, Slabs, ArchOf<W>>(structure, rays, out, traversal.grouping);
                else
                    throw std::runtime_error(fmt::format("--simd {} with --accel {}: packet traversal not built yet",
                                                         to_string(W), to_string(accel.kind())));
            });
        });
    });
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

void occlude_stream(const AnyAccel& accel, std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                    StreamTraversal traversal, TriangleTest test) {
    trace_stream<true>(accel, rays, occluded, traversal, test);
}

void intersect_stream(const AnyAccel& accel, std::span<const Ray> rays, std::span<Hit> hits, StreamTraversal traversal,
                      TriangleTest test) {
    trace_stream<false>(accel, rays, hits, traversal, test);
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
