#pragma once
// The SAH sweep over one axis's sorted events (Wald and Havran 2006, algorithm 4.2): the counts of
// triangles entirely below, lying in and entirely above each candidate plane, and the cheapest
// plane. It is the builder's hottest loop, so it is written for speed:
//
// - one event per step without branches: running counts of the events that end or lie flat (not
//   above any later plane), start or lie flat (below any later plane) and lie flat; a candidate is
//   evaluated at the last event of each group of equal positions (ends, planars, starts in that
//   order) with the counts from the group's first event;
// - candidates are compared by their area-weighted counts (A_below n_below + A_above n_above,
//   times 1 - b_e with an empty side); non-negative doubles order like their bit patterns, so the
//   minimum is kept with integer conditional moves (which candidate wins next is unpredictable),
//   and the winner is remembered as a tag, its event's offset << 1 | whether planar triangles go
//   below. The earliest candidate wins a tie, and for planar triangles the side above wins a tie
//   (Wald and Havran).
#include <bit>
#include <cstdint>
#include <limits>
#include <span>

#include "accel/kdtree/kd_event.h"

namespace trident::kd {

/// What the sweep needs of a node on one axis: its triangle count and its cell, as the half
/// surface areas of the two children as functions of the plane position p:
/// below: below_base + p * side, above: above_base - p * side.
struct SweepSetup {
    std::int64_t triangles;
    double below_base, above_base, side;
    float lo, hi;  // the cell on this axis
    double empty_scale;
};

struct SweepBest {
    static constexpr std::uint64_t kNone = ~std::uint64_t(0);
    std::uint64_t key = kNone;  // bits of the weighted count
    std::uint64_t tag = 0;      // event offset << 1 | planar triangles below

    bool found() const { return key != kNone; }
    double weighted() const { return std::bit_cast<double>(key); }
};

namespace detail {

/// The running state of a sweep between events.
struct SweepState {
    std::int64_t not_above = 0, below = 0, planar = 0;     // over the events so far
    std::int64_t below_at_group = 0, planar_at_group = 0;  // at the first event of the current group
    SweepBest best;
};

inline std::uint32_t position_bits(const Event& e) { return std::bit_cast<std::uint32_t>(e.position); }

inline void consider(const SweepSetup& s, float position, double below_area, double above_area, std::int64_t nb,
                     std::int64_t na, std::uint64_t tag, SweepBest& best) {
    double weighted = below_area * double(nb) + above_area * double(na);
    if (nb * na == 0) [[unlikely]] {
        // A child equal to the node (the other one flat and empty) makes no progress.
        if ((nb == 0 && position == s.lo) || (na == 0 && position == s.hi)) return;
        weighted *= s.empty_scale;  // pbrt applies the bonus to the intersection term only
    }
    const auto key = std::bit_cast<std::uint64_t>(weighted);
    const bool better = key < best.key;
    best.tag = better ? tag : best.tag;
    best.key = better ? key : best.key;
}

/// Event i of the list. Equal positions have equal bits (events store +0 for -0).
inline void sweep_step(std::span<const Event> events, std::size_t i, const SweepSetup& s, SweepState& state) {
    const float position = events[i].position;
    const std::uint32_t bits = position_bits(events[i]);
    const std::uint32_t type = events[i].prim_type & 3u;
    const bool group_starts = i == 0 || position_bits(events[i - 1]) != bits;
    state.below_at_group = group_starts ? state.below : state.below_at_group;
    state.planar_at_group = group_starts ? state.planar : state.planar_at_group;
    state.not_above += type != std::uint32_t(EventType::start);
    state.below += type != std::uint32_t(EventType::end);
    state.planar += type == std::uint32_t(EventType::planar);
    if (i + 1 < events.size() && position_bits(events[i + 1]) == bits) return;

    const double scaled = double(position) * s.side;
    const double below_area = s.below_base + scaled, above_area = s.above_base - scaled;
    const std::int64_t in_plane = state.planar - state.planar_at_group, above = s.triangles - state.not_above;
    consider(s, position, below_area, above_area, state.below_at_group, above + in_plane, std::uint64_t(i) << 1,
             state.best);
    if (in_plane > 0) [[unlikely]]
        consider(s, position, below_area, above_area, state.below_at_group + in_plane, above,
                 std::uint64_t(i) << 1 | 1u, state.best);
}

}  // namespace detail

/// The cheapest plane among the events of one axis, sorted in the sweep order; none found when
/// every candidate would leave a child equal to the node.
inline SweepBest sweep_events(std::span<const Event> events, const SweepSetup& setup) {
    detail::SweepState state;
    for (std::size_t i = 0; i < events.size(); ++i) detail::sweep_step(events, i, setup, state);
    return state.best;
}

}  // namespace trident::kd
