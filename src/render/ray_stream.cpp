#include "render/ray_stream.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <type_traits>

#include "render/trace.h"
#include "simd/packet.h"

namespace trident {
namespace {

bool has_work(const Ray& ray) { return ray.tmax > ray.tmin; }

int octant_of(const Vec3f& d) {
    return (std::signbit(d.x) ? 1 : 0) | (std::signbit(d.y) ? 2 : 0) | (std::signbit(d.z) ? 4 : 0);
}

/// Rays waiting for a packet, with the stream positions their results go to.
template <std::size_t Lanes>
struct PendingPacket {
    std::array<Ray, Lanes> rays;
    std::array<std::size_t, Lanes> index;
    std::size_t lanes = 0;
};

/// Writes one result per ray: the any-hit bit or the closest hit.
template <bool AnyHit>
using Result = std::conditional_t<AnyHit, std::uint8_t, Hit>;

template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Structure>
void trace_single(const Structure& structure, std::span<const Ray> rays, std::span<Result<AnyHit>> out) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
        NoCounters counters;
        if constexpr (AnyHit)
            out[i] = has_work(rays[i]) && structure.template occluded<Test, Slabs>(rays[i], counters);
        else
            out[i] = has_work(rays[i]) ? structure.template intersect<Test, Slabs>(rays[i], counters) : Hit{};
    }
}

template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Arch, class Structure>
void trace_packets(const Structure& structure, std::span<const Ray> rays, std::span<Result<AnyHit>> out,
                   PacketGrouping grouping) {
    constexpr std::size_t kLanes = RayPacket<Arch>::width;
    using Pending = PendingPacket<kLanes>;
    auto flush = [&](Pending& pending) {
        if (pending.lanes == 0) return;
        const RayPacket<Arch> packet(std::span<const Ray>(pending.rays.data(), pending.lanes));
        NoCounters counters;
        if constexpr (AnyHit) {
            const std::uint32_t bits = simd::mask_bits(structure.template occluded<Test, Slabs>(packet, counters));
            for (std::size_t k = 0; k < pending.lanes; ++k) out[pending.index[k]] = (bits >> k) & 1u;
        } else {
            HitPacket<Arch> hits(packet);
            structure.template intersect<Test, Slabs>(packet, hits, counters);
            std::array<Hit, kLanes> lane_hits;
            hits.store(std::span<Hit>(lane_hits.data(), pending.lanes));
            for (std::size_t k = 0; k < pending.lanes; ++k) out[pending.index[k]] = lane_hits[k];
        }
        pending.lanes = 0;
    };
    auto add = [&](Pending& pending, std::size_t i) {
        pending.rays[pending.lanes] = rays[i];
        pending.index[pending.lanes++] = i;
        if (pending.lanes == kLanes) flush(pending);
    };

    std::array<Pending, 8> by_octant;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!has_work(rays[i])) {
            out[i] = Result<AnyHit>{};
            continue;
        }
        add(by_octant[grouping == PacketGrouping::by_octant ? octant_of(rays[i].dir) : 0], i);
    }
    // Leftovers of the octant groups share packets rather than each filling a few lanes.
    Pending mixed;
    for (Pending& pending : by_octant)
        for (std::size_t k = 0; k < pending.lanes; ++k) add(mixed, pending.index[k]);
    flush(mixed);
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

// Chunks of consecutive rays: large enough to fill every octant's packets several times.
constexpr std::size_t kChunkRays = 1024;

template <bool AnyHit>
void trace_stream_parallel(const AnyAccel& accel, std::span<const Ray> rays, std::span<Result<AnyHit>> out,
                           StreamTraversal traversal, TriangleTest test) {
    if (out.size() != rays.size()) throw std::invalid_argument("trace stream: one result per ray is needed");
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), kChunkRays), [&](const auto& range) {
        trace_stream<AnyHit>(accel, rays.subspan(range.begin(), range.size()), out.subspan(range.begin(), range.size()),
                             traversal, test);
    });
}

}  // namespace

const char* to_string(PacketGrouping grouping) {
    return grouping == PacketGrouping::by_octant ? "by direction octant" : "in primary-packet order";
}

void occlude_stream(const AnyAccel& accel, std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                    StreamTraversal traversal, TriangleTest test) {
    trace_stream<true>(accel, rays, occluded, traversal, test);
}

void intersect_stream(const AnyAccel& accel, std::span<const Ray> rays, std::span<Hit> hits,
                      StreamTraversal traversal, TriangleTest test) {
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
