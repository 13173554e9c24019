#pragma once
// The check every structure's packet tests make: trace rays in packets and compare each lane with
// the single-ray traversal of the same ray, closest hit bit for bit (triangle, t, u, v) and the
// any-hit answer; lanes not traced (switched off, past the rays, or with tmin > tmax) must keep
// the record they arrived with and never be reported occluded. Each structure says how it traces
// a packet and a ray, and which differences it allows (the BVH: ties between triangles at one t).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <utility>
#include <vector>

#include "accel/accel_stats.h"
#include "core/ray.h"
#include "simd/packet.h"

namespace trident::testing {

/// Which lanes of each packet to switch off, by lane index.
using LaneFilter = std::function<bool(std::size_t)>;

inline bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }
inline bool same_bits(const Hit& a, const Hit& b) {
    return a.triangle == b.triangle && same_bits(a.t, b.t) && same_bits(a.u, b.u) && same_bits(a.v, b.v);
}

/// The raw lanes of a hit packet (misses as they are, not as Hit{}).
template <class Arch>
struct HitLanes {
    static constexpr std::size_t width = HitPacket<Arch>::width;
    std::array<std::uint32_t, width> triangle;
    std::array<float, width> t, u, v;

    explicit HitLanes(const HitPacket<Arch>& hits) {
        hits.triangle.store_unaligned(triangle.data());
        hits.t.store_unaligned(t.data());
        hits.u.store_unaligned(u.data());
        hits.v.store_unaligned(v.data());
    }
    Hit lane(std::size_t i) const { return {triangle[i], t[i], u[i], v[i]}; }
};

/// Whether the traced lanes agree on the sign of every direction component (dir < 0): then a
/// structure whose packets take one child order for all lanes takes each lane's single-ray order.
inline bool lanes_share_octant(std::span<const Ray> rays, const std::vector<bool>& traced) {
    int octant = -1;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!traced[i]) continue;
        const int lane = int(rays[i].dir.x < 0.0f) | int(rays[i].dir.y < 0.0f) << 1 | int(rays[i].dir.z < 0.0f) << 2;
        if (octant >= 0 && lane != octant) return false;
        octant = lane;
    }
    return true;
}

/// What a comparison found, lane by lane.
struct PacketComparison {
    std::size_t lanes = 0;        // lanes compared
    std::size_t hits = 0;         // of them, single-ray hits (to see the test is not vacuous)
    std::size_t ties = 0;         // lanes that kept another triangle hit at the same t (allowed)
    std::size_t closest = 0;      // lanes whose closest hit differs otherwise
    std::size_t shared_ties = 0;  // ties in packets whose lanes share an octant, where none may occur
    std::size_t occluded = 0;     // lanes whose any-hit answer differs
    std::size_t untouched = 0;    // lanes not traced whose hit record changed anyway
    std::size_t padding = 0;      // lanes not traced reported occluded

    void require_agreement() const {
        CHECK(lanes > 0);
        CHECK(closest == 0);
        CHECK(shared_ties == 0);
        CHECK(occluded == 0);
        CHECK(untouched == 0);
        CHECK(padding == 0);
    }
};

/// A tie rule that allows none: every difference counts.
inline bool no_ties(const Ray&, const Hit&, const Hit&) { return false; }

/// Traces `rays` in packets of `rays_per_packet` consecutive rays (the width when 0; the last
/// packet may be partial) with the lanes `off` names switched off, and compares every lane.
/// - `trace_packet(packet, hits)` traces closest hit into `hits` and returns the any-hit lanes
///   (as mask bits) of the same packet;
/// - `intersect(ray)` and `occluded(ray)` are the single-ray traversal's answers;
/// - `is_tie(ray, got, expected)` says whether a different closest hit is another triangle at the
///   same t, which the caller allows (counted in `ties`, not in `closest`).
template <class Arch, class TracePacket, class Intersect, class Occluded, class IsTie = decltype(&no_ties)>
PacketComparison compare_packet_lanes(std::span<const Ray> rays, std::size_t rays_per_packet, const LaneFilter& off,
                                      TracePacket&& trace_packet, Intersect&& intersect, Occluded&& occluded,
                                      IsTie&& is_tie = no_ties) {
    constexpr std::size_t width = RayPacket<Arch>::width;
    using Mask = typename RayPacket<Arch>::Mask;
    const std::size_t step = rays_per_packet == 0 ? width : std::min(rays_per_packet, width);
    PacketComparison out;
    for (std::size_t first = 0; first < rays.size(); first += step) {
        const std::span<const Ray> chunk = rays.subspan(first, std::min(step, rays.size() - first));
        RayPacket<Arch> packet(chunk);
        std::array<bool, width> live{};
        for (std::size_t i = 0; i < chunk.size(); ++i) live[i] = !(off && off(i));
        packet.active = packet.active & Mask::load_unaligned(live.data());

        const HitPacket<Arch> arrived(packet);
        HitPacket<Arch> hits(packet);
        const std::uint32_t occluded_lanes = trace_packet(std::as_const(packet), hits);
        const HitLanes<Arch> before(arrived), after(hits);
        std::vector<bool> traced(width);
        for (std::size_t i = 0; i < chunk.size(); ++i) traced[i] = live[i] && chunk[i].tmin <= chunk[i].tmax;
        const bool shared_octant = lanes_share_octant(chunk, traced);

        for (std::size_t i = 0; i < width; ++i) {
            if (!traced[i]) {
                out.untouched += !same_bits(before.lane(i), after.lane(i));
                out.padding += (occluded_lanes >> i) & 1u;
                continue;
            }
            ++out.lanes;
            const Hit expected = intersect(chunk[i]);
            out.hits += expected.is_hit();
            const Hit got = after.lane(i).is_hit() ? after.lane(i) : Hit{};
            if (!same_bits(got, expected)) {
                if (is_tie(chunk[i], got, expected)) {
                    ++out.ties;
                    out.shared_ties += shared_octant;
                } else {
                    ++out.closest;
                }
            }
            out.occluded += bool((occluded_lanes >> i) & 1u) != occluded(chunk[i]);
        }
    }
    return out;
}

/// The counters of packets against those of their lanes traced alone, packet by packet: a packet
/// counts at least its busiest lane's work and at most all its lanes' together.
struct PacketWorkTally {
    TraversalCounters packets, lanes;  // summed over the packets added
    std::size_t counted = 0;           // packets added
    std::size_t below_busiest = 0;     // packets counting less than their busiest lane
    std::size_t above_sum = 0;         // packets counting more than their lanes together

    /// Adds one packet's counters `packet` for the rays `chunk`; `count_ray(ray, counters)`
    /// traces a ray alone.
    template <class CountRay>
    void add(const TraversalCounters& packet, std::span<const Ray> chunk, CountRay&& count_ray) {
        TraversalCounters busiest, sum;
        for (const Ray& ray : chunk) {
            TraversalCounters one;
            count_ray(ray, one);
            busiest.nodes_visited = std::max(busiest.nodes_visited, one.nodes_visited);
            busiest.triangles_tested = std::max(busiest.triangles_tested, one.triangles_tested);
            sum += one;
        }
        below_busiest +=
            packet.nodes_visited < busiest.nodes_visited || packet.triangles_tested < busiest.triangles_tested;
        above_sum += packet.nodes_visited > sum.nodes_visited || packet.triangles_tested > sum.triangles_tested;
        packets += packet;
        lanes += sum;
        ++counted;
    }

    void require_bounds() const {
        CHECK(counted > 0);
        CHECK(below_busiest == 0);
        CHECK(above_sum == 0);
        // The point of packets: coherent lanes share most of their nodes.
        CHECK(2 * packets.nodes_visited < lanes.nodes_visited);
    }
};

}  // namespace trident::testing
