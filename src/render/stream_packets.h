#pragma once
// How a list of secondary rays is cut into packets: in list order (the order of the primary packets
// that made them, which keeps shadow rays coherent) or regrouped by direction octant (incoherent
// diffuse rays: lanes of a packet then share their slab-test signs). One rule for our traversals
// (ray_stream.h) and for Embree's packet rows in the benchmark, so both trace the same packets.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <span>

#include "core/ray.h"

namespace trident {

enum class PacketGrouping { in_order, by_octant };

inline const char* to_string(PacketGrouping grouping) {
    return grouping == PacketGrouping::by_octant ? "by direction octant" : "in primary-packet order";
}

/// Rays with tmax <= tmin are not traced: unoccluded, no hit.
inline bool is_traced(const Ray& ray) { return ray.tmax > ray.tmin; }

/// The widest packet a stream is cut into (16 lanes: AVX-512, Embree's rtcIntersect16).
inline constexpr std::size_t kMaxStreamPacketLanes = 16;
/// Consecutive rays per parallel task: enough to fill every octant's packets several times.
inline constexpr std::size_t kStreamChunkRays = 1024;

/// per_chunk(first, last) over [0, ray_count) in chunks of about kStreamChunkRays, on oneTBB's threads.
template <class PerChunk>
void for_each_stream_chunk(std::size_t ray_count, PerChunk&& per_chunk) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ray_count, kStreamChunkRays),
                      [&](const auto& range) { per_chunk(range.begin(), range.end()); });
}

/// per_packet(std::span<const std::size_t> indices) for packets of at most `lanes` (<= 16) traced
/// rays of `rays`, grouped as `grouping` says. Octant groups fill whole packets first; their
/// leftovers then share packets rather than each filling a few lanes.
template <class PerPacket>
void for_each_stream_packet(std::span<const Ray> rays, std::size_t lanes, PacketGrouping grouping,
                            PerPacket&& per_packet) {
    if (grouping == PacketGrouping::in_order) {
        // The same packets as the octant groups' loop below with one group, the count kept in a
        // register: that loop's count, in an array indexed by octant, went through memory with
        // every ray (a store, then a load of it), 9% of Teapot's 8-lane shadow packets (perf).
        std::array<std::size_t, kMaxStreamPacketLanes> index;
        std::size_t count = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (!is_traced(rays[i])) continue;
            index[count++] = i;
            if (count == lanes) {
                per_packet(std::span<const std::size_t>(index.data(), count));
                count = 0;
            }
        }
        if (count) per_packet(std::span<const std::size_t>(index.data(), count));
        return;
    }
    struct Pending {
        std::array<std::size_t, kMaxStreamPacketLanes> index;
        std::size_t lanes = 0;
    };
    auto add = [&](Pending& pending, std::size_t i) {
        pending.index[pending.lanes++] = i;
        if (pending.lanes == lanes) {
            per_packet(std::span<const std::size_t>(pending.index.data(), pending.lanes));
            pending.lanes = 0;
        }
    };
    auto octant_of = [](const Vec3f& d) {
        return (std::signbit(d.x) ? 1 : 0) | (std::signbit(d.y) ? 2 : 0) | (std::signbit(d.z) ? 4 : 0);
    };
    std::array<Pending, 8> by_octant;
    for (std::size_t i = 0; i < rays.size(); ++i)
        if (is_traced(rays[i])) add(by_octant[octant_of(rays[i].dir)], i);
    Pending mixed;
    for (Pending& pending : by_octant)
        for (std::size_t k = 0; k < pending.lanes; ++k) add(mixed, pending.index[k]);
    if (mixed.lanes) per_packet(std::span<const std::size_t>(mixed.index.data(), mixed.lanes));
}

}  // namespace trident
