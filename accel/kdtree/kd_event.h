#pragma once
// Split-plane events of the kd-tree builder (Wald and Havran, "On building fast kd-trees for ray
// tracing, and on doing that in O(N log N)", RT 2006, section 4). Each triangle's bounds in a node
// give, per axis, a start and an end event, or one planar event when the bounds are flat there.
// A node keeps one list per axis, sorted by position and, at equal positions, ends before planars
// before starts: the order in which the SAH sweep must count them.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <span>

#include "accel/kdtree/radix_sort.h"

// The builder's hot loops (the SAH sweep, the filtering of event lists, the handing of a node's
// triangles to its children) have AVX-512 forms that give the same results as their scalar forms;
// the scalar forms serve where AVX-512 (F, VL, DQ and BW, for byte masks) is not compiled in.
#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512DQ__) && defined(__AVX512BW__)
#include <immintrin.h>
#define TRIDENT_KD_AVX512 1
#else
#define TRIDENT_KD_AVX512 0
#endif

namespace trident::kd {

enum class EventType : std::uint32_t { end = 0, planar = 1, start = 2 };

/// 8 bytes: the plane position and the node-local triangle index with the event type.
struct Event {
    float position;
    std::uint32_t prim_type;  // local triangle index << 2 | type

    static Event make(float position, std::uint32_t prim, EventType type) {
        // +0 for -0, so that equal positions are equal bit patterns and sort together.
        return {position + 0.0f, prim << 2 | std::uint32_t(type)};
    }
    std::uint32_t prim() const { return prim_type >> 2; }
    EventType type() const { return EventType(prim_type & 3u); }
};
static_assert(sizeof(Event) == 8);

/// The sweep order: position, then end < planar < start.
inline bool event_before(const Event& a, const Event& b) {
    return a.position < b.position || (a.position == b.position && (a.prim_type & 3u) < (b.prim_type & 3u));
}

/// The order-preserving integer image of a float: negatives reversed, below positives.
inline std::uint32_t ordered_bits(float x) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(x);
    return bits ^ ((bits >> 31) ? 0xFFFFFFFFu : 0x80000000u);
}

/// Sorts a list into the sweep order: by radix when large, by comparison when small. The radix
/// sort orders by position alone and keeps the input order otherwise, so a list must be written
/// ends first, then planars, then starts.
inline void sort_events(std::span<Event> events, std::span<Event> scratch) {
    constexpr std::size_t kRadixFrom = 4096;
    if (events.size() >= kRadixFrom)
        radix_sort(events, scratch, [](const Event& e) { return ordered_bits(e.position); });
    else
        std::sort(events.begin(), events.end(), event_before);
}

/// Merges the sorted `fresh` events with the sorted events already stored at the tail of `out`
/// (out[fresh.size() ...]) into all of `out`. Fresh events are few: each finds its place by binary
/// search and the kept events before it move down as one block, which never overtakes reading.
inline void merge_into_tail(std::span<const Event> fresh, std::span<Event> out) {
    Event* write = out.data();
    const Event* read = out.data() + fresh.size();
    const Event* const end = out.data() + out.size();
    for (const Event& f : fresh) {
        const Event* place = std::upper_bound(read, end, f, event_before);
        write = std::copy(read, place, write);
        *write++ = f;
        read = place;
    }
}

}  // namespace trident::kd
