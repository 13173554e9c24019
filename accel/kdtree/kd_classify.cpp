// The classification of a node's triangles by the chosen plane and the split of its sorted event
// lists into its children's, keeping them sorted (Wald and Havran, "On building fast kd-trees for
// ray tracing, and on doing that in O(N log N)", RT 2006, sections 4.3 and 4.4): one pass over the
// split axis's events gives each triangle its side, one pass over the triangles gives each child
// its triangles, and one filtered copy per axis gives each child its events; only the straddlers
// get new events (clipped, sorted and merged in, with perfect splits).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>

#include "accel/kdtree/clip_triangle.h"
#include "accel/kdtree/kd_builder.h"

namespace trident::kd {

namespace {

/// Straddlers clipped per task (perfect splits).
constexpr std::size_t kClipGrain = 1024;

/// Where a triangle goes relative to the split plane; straddlers also get fresh events.
constexpr std::uint8_t kBelow = 1, kAbove = 2, kBoth = 3, kFreshEvents = 4;

/// Per triangle of a node: per child, its index there << 2 | 1 when the child takes the triangle's
/// events from the node's lists, else 0.
using Destination = std::array<std::uint32_t, 2>;

/// Copies the events a child takes (Children: 0 below, 1 above, 2 both) renumbered to out[c],
/// advancing it; without AVX-512, out[c] may be written one past the events kept. keep[c] is 0 for
/// a child that builds no lists (its out[c] is a sink).
template <int Children>
void filter_events(std::span<const Event> events, std::span<const Destination> dest,
                   const std::array<std::uint32_t, 2>& keep, std::array<Event*, 2>& out) {
#if TRIDENT_KD_AVX512
    // Eight events at a time: their destinations gathered, each child's events compressed to the
    // front of a register and stored under a mask of as many lanes. Nothing is written past the
    // events kept.
    static_assert(sizeof(Destination) == 8 && sizeof(Event) == 8);
    const auto* const source = reinterpret_cast<const long long*>(events.data());
    const auto* const table = reinterpret_cast<const long long*>(dest.data());
    auto* below = reinterpret_cast<long long*>(out[0]);
    auto* above = reinterpret_cast<long long*>(out[1]);
    const __mmask8 keep_below = keep[0] ? 0xFF : 0, keep_above = keep[1] ? 0xFF : 0;
    // An event is position | prim_type << 32; a destination below | above << 32.
    const __m512i position_and_type = _mm512_set1_epi64(0x3FFFFFFFFll);
    const __m512i below_bit = _mm512_set1_epi64(1), above_bit = _mm512_set1_epi64(1ll << 32);
    const std::size_t n = events.size();
    for (std::size_t i = 0; i < n; i += 8) {
        const __mmask8 lanes = n - i >= 8 ? 0xFF : __mmask8((1u << (n - i)) - 1u);
        const __m512i e = _mm512_maskz_loadu_epi64(lanes, source + i);
        const __m512i d =
            _mm512_mask_i64gather_epi64(_mm512_setzero_si512(), lanes, _mm512_maskz_srli_epi64(0xFF, e, 34), table, 8);
        if constexpr (Children != 1) {
            const __mmask8 take = _mm512_mask_test_epi64_mask(keep_below, d, below_bit);
            const __m512i renumbered =
                _mm512_ternarylogic_epi64(e, _mm512_maskz_slli_epi64(0xFF, d, 32), position_and_type, 0xE4);
            _mm512_mask_storeu_epi64(below, __mmask8((1u << std::popcount(unsigned(take))) - 1u),
                                     _mm512_maskz_compress_epi64(take, renumbered));
            below += std::popcount(unsigned(take));
        }
        if constexpr (Children != 0) {
            const __mmask8 take = _mm512_mask_test_epi64_mask(keep_above, d, above_bit);
            const __m512i renumbered = _mm512_ternarylogic_epi64(e, d, position_and_type, 0xE4);
            _mm512_mask_storeu_epi64(above, __mmask8((1u << std::popcount(unsigned(take))) - 1u),
                                     _mm512_maskz_compress_epi64(take, renumbered));
            above += std::popcount(unsigned(take));
        }
    }
    out = {reinterpret_cast<Event*>(below), reinterpret_cast<Event*>(above)};
#else
    Event* below = out[0];
    Event* above = out[1];
    for (const Event& e : events) {
        const Destination& d = dest[e.prim()];
        const std::uint32_t type = e.prim_type & 3u;
        if constexpr (Children != 1) {
            *below = {e.position, (d[0] & ~3u) | type};
            below += d[0] & keep[0];
        }
        if constexpr (Children != 0) {
            *above = {e.position, (d[1] & ~3u) | type};
            above += d[1] & keep[1];
        }
    }
    out = {below, above};
#endif
}

/// What distribute() found: the straddlers, and per child its one-sided triangles and how many of
/// them are flat on each axis (one event there instead of two).
struct Distributed {
    std::size_t straddler_count = 0;
    std::array<std::uint32_t, 2> kept{0, 0};
    std::array<std::array<std::size_t, 3>, 2> flat{};
};

/// One pass over a node's triangles by side (kBelow, kAbove or kBoth): the one-sided ones appended
/// in order to their child's prims and flat axes, each triangle's Destination (its index there << 2
/// | 1 for the child that takes it, 0 for a straddler), the straddlers' local indices listed.
/// child_prims[c] and child_flat[c] hold n + 1 entries and dest n + 16 (the vector form stores
/// whole registers); entries past those kept and past n are scratch.
Distributed distribute(std::span<const std::uint8_t> side, std::span<const std::uint32_t> prims,
                       std::span<const std::uint8_t> flat_axes, std::array<std::uint32_t*, 2> child_prims,
                       std::array<std::uint8_t*, 2> child_flat, Destination* dest, std::uint32_t* straddlers) {
    Distributed out;
    const std::size_t n = prims.size();
#if TRIDENT_KD_AVX512
    // Sixteen triangles at a time: each child's prims and flat axes compressed to the front of a
    // register and stored under a mask of as many lanes (a compressing store to memory is slow on
    // some CPUs). A triangle's index in its child is its rank among the lanes going there, which
    // expanding 0, 1, 2, ... into those lanes gives. The zero-masked forms of some intrinsics,
    // with every lane set, are the plain instructions: GCC 12 warns that the plain forms read an
    // undefined vector.
    static_assert(sizeof(Destination) == 8);
    const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const __m512i first_pairs = _mm512_setr_epi32(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
    const __m512i last_pairs = _mm512_add_epi32(first_pairs, _mm512_set1_epi32(8));
    const __m512i one = _mm512_set1_epi32(1);
    auto store_first = [](auto* to, __mmask16 take, __m512i values) {
        const auto count = unsigned(std::popcount(unsigned(take)));
        const auto stored = __mmask16((1u << count) - 1u);
        if constexpr (sizeof(*to) == 4)
            _mm512_mask_storeu_epi32(to, stored, _mm512_maskz_compress_epi32(take, values));
        else
            _mm512_mask_cvtepi32_storeu_epi8(to, stored, _mm512_maskz_compress_epi32(take, values));
        return count;
    };
    auto* const dest_words = reinterpret_cast<std::uint32_t*>(dest);
    for (std::size_t i = 0; i < n; i += 16) {
        const __mmask16 lanes = n - i >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << (n - i)) - 1u);
        const __m512i s = _mm512_maskz_cvtepu8_epi32(0xFFFF, _mm_maskz_loadu_epi8(lanes, side.data() + i));
        const __m512i flat = _mm512_maskz_cvtepu8_epi32(0xFFFF, _mm_maskz_loadu_epi8(lanes, flat_axes.data() + i));
        const __m512i prim = _mm512_maskz_loadu_epi32(lanes, prims.data() + i);
        const __mmask16 goes[2] = {_mm512_cmpeq_epi32_mask(s, _mm512_set1_epi32(kBelow)),
                                   _mm512_cmpeq_epi32_mask(s, _mm512_set1_epi32(kAbove))};
        const __mmask16 straddles = _mm512_mask_cmpeq_epi32_mask(lanes, s, _mm512_set1_epi32(kBoth));
        out.straddler_count +=
            store_first(straddlers + out.straddler_count, straddles, _mm512_add_epi32(iota, _mm512_set1_epi32(int(i))));
        __m512i to[2];
        for (int c = 0; c < 2; ++c) {
            const std::uint32_t at = out.kept[c];
            const __m512i index =
                _mm512_add_epi32(_mm512_maskz_expand_epi32(goes[c], iota), _mm512_set1_epi32(int(at)));
            to[c] = _mm512_maskz_or_epi32(goes[c], _mm512_maskz_slli_epi32(0xFFFF, index, 2), one);
            store_first(child_flat[c] + at, goes[c], flat);
            out.kept[c] += store_first(child_prims[c] + at, goes[c], prim);
            for (int axis = 0; axis < 3; ++axis)
                out.flat[c][axis] += unsigned(
                    std::popcount(unsigned(_mm512_mask_test_epi32_mask(goes[c], flat, _mm512_set1_epi32(1 << axis)))));
        }
        _mm512_storeu_si512(dest_words + 2 * i, _mm512_permutex2var_epi32(to[0], first_pairs, to[1]));
        _mm512_storeu_si512(dest_words + 2 * i + 16, _mm512_permutex2var_epi32(to[0], last_pairs, to[1]));
    }
#else
    // Without branches (which side is unpredictable): each triangle is written to both children,
    // and the next triangle overwrites it where it does not stay.
    std::array<std::uint32_t, 2> at{0, 0};
    for (std::size_t i = 0; i < n; ++i) {
        const unsigned s = side[i], flat = flat_axes[i];
        straddlers[out.straddler_count] = std::uint32_t(i);
        out.straddler_count += s == kBoth;
        const std::array<std::uint32_t, 2> goes{s == kBelow, s == kAbove};
        for (int c = 0; c < 2; ++c) {
            child_prims[c][at[c]] = prims[i];
            child_flat[c][at[c]] = std::uint8_t(flat);
            dest[i][c] = (at[c] << 2 | 1u) & -goes[c];
            at[c] += goes[c];
            for (int axis = 0; axis < 3; ++axis) out.flat[c][axis] += (flat >> axis) & goes[c];
        }
    }
    out.kept = at;
#endif
    return out;
}

}  // namespace

std::array<NodeWork, 2> SahBuilder::split_node(const NodeWork& node, const Split& split, bool children_may_split,
                                               ThreadScratch& scratch) const {
    const std::size_t n = node.size();
    const int k = split.axis;
    const float p = split.position;
    const bool perfect = options_.perfect_splits;
    const ScratchArena::Mark temp_mark = scratch.temp.mark();

    // Classify: one pass over the split axis's events, in three runs split at the plane's
    // group: before it (events below the plane and ends on it), its planars, after it (starts
    // on it and events above). A triangle that ends in the first run lies below (its start
    // comes earlier and changes nothing), one that starts in the last lies above (its end
    // comes later and changes nothing), a planar one goes where its run says, and one that
    // does neither straddles. Each event stores its side, or writes to a sink past the
    // triangles when it says nothing: stores alone, no read of the side before.
    const std::span<const Event> split_events = node.events[k];
    const auto first_planar = std::size_t(
        std::lower_bound(split_events.begin(), split_events.end(), Event::make(p, 0, EventType::planar), event_before) -
        split_events.begin());
    const auto first_start =
        std::size_t(std::lower_bound(split_events.begin() + std::ptrdiff_t(first_planar), split_events.end(),
                                     Event::make(p, 0, EventType::start), event_before) -
                    split_events.begin());
    const std::span<std::uint8_t> side = scratch.temp.allocate<std::uint8_t>(n + 1);
    std::fill(side.begin(), side.end(), kBoth);
    {
        // Local copies: the byte stores below may alias anything whose address is taken, and
        // the loop bounds would be read again from memory at every step.
        std::uint8_t* const sides = side.data();
        const Event* const events = split_events.data();
        const std::size_t planars_from = first_planar, starts_from = first_start, end = split_events.size();
        const auto sink = std::uint32_t(n);
        // The event's triangle, or the sink for an event of the silent type, without a branch:
        // the types come mixed, and a branch on them is mispredicted.
        auto target = [sink](const Event& e, EventType silent) {
            const std::uint32_t prim = e.prim();
            const std::uint32_t is_silent = -std::uint32_t((e.prim_type & 3u) == std::uint32_t(silent));
            return prim ^ ((prim ^ sink) & is_silent);
        };
        for (std::size_t i = 0; i < planars_from; ++i) sides[target(events[i], EventType::start)] = kBelow;
        const std::uint8_t in_plane = split.planars_below ? kBelow : kAbove;
        for (std::size_t i = planars_from; i < starts_from; ++i) sides[events[i].prim()] = in_plane;
        for (std::size_t i = starts_from; i < end; ++i) sides[target(events[i], EventType::end)] = kAbove;
    }

    // One pass over the triangles: the straddlers listed, the one-sided triangles given to
    // their child (with their new local indices in `dest`, the straddlers' set further down).
    // Each child's arrays are allocated for all n triangles, since its size is known only
    // after the pass.
    std::array<std::span<std::uint32_t>, 2> child_prims;
    std::array<std::span<std::uint8_t>, 2> child_flat;
    for (int c = 0; c < 2; ++c) {
        child_prims[c] = scratch.kept.allocate<std::uint32_t>(n + 1);
        child_flat[c] = scratch.kept.allocate<std::uint8_t>(n + 1);
    }
    const std::span<Destination> dest = scratch.temp.allocate<Destination>(n + 16);
    const std::span<std::uint32_t> all_straddlers = scratch.temp.allocate<std::uint32_t>(n);
    const Distributed one_sided =
        distribute(side.first(n), node.prims, node.flat_axes, {child_prims[0].data(), child_prims[1].data()},
                   {child_flat[0].data(), child_flat[1].data()}, dest.data(), all_straddlers.data());
    const std::size_t straddler_count = one_sided.straddler_count;
    const std::array<std::uint32_t, 2>& kept_count = one_sided.kept;
    const std::span<const std::uint32_t> straddlers = all_straddlers.first(straddler_count);

    // The straddlers' bounds in each child. Without perfect splits they are the node's bounds
    // clamped to the child's cell: unchanged off the split axis, so their events there are the
    // node's, and on the split axis the plane replaces the end (below) or the start (above).
    // Perfect splits clip them (which may show that a triangle misses one child) and give
    // them fresh events on every axis.
    std::array<Aabb, 2> cells{node.cell, node.cell};
    cells[0].hi[k] = p;
    cells[1].lo[k] = p;
    std::span<Aabb> straddler_bounds;
    std::array<std::size_t, 2> fresh_count{0, 0};
    std::array<std::array<std::size_t, 3>, 2> flat_fresh{};
    if (perfect) {
        straddler_bounds = scratch.temp.allocate<Aabb>(2 * straddler_count);
        auto bound_straddlers = [&](std::size_t begin, std::size_t end) {
            for (std::size_t j = begin; j < end; ++j) {
                const std::uint32_t i = straddlers[j];
                const TriangleId id = node.prims[i];
                for (int c = 0; c < 2; ++c) straddler_bounds[2 * j + c] = intersection(bounds_[id], cells[c]);
                const auto below = clipped_triangle_bounds(triangles_[id], cells[0]);
                const auto above = clipped_triangle_bounds(triangles_[id], cells[1]);
                // Both empty only through rounding, for a triangle touching the plane: keep
                // the clamped boxes on both sides.
                if (below || above) side[i] = std::uint8_t((below ? kBelow : 0) | (above ? kAbove : 0));
                if (below) straddler_bounds[2 * j] = *below;
                if (above) straddler_bounds[2 * j + 1] = *above;
                side[i] |= kFreshEvents;
            }
        };
        if (straddler_count >= 2 * kClipGrain)
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, straddler_count, kClipGrain),
                              [&](const tbb::blocked_range<std::size_t>& r) { bound_straddlers(r.begin(), r.end()); });
        else
            bound_straddlers(0, straddler_count);
        for (std::size_t j = 0; j < straddler_count; ++j)
            for (int c = 0; c < 2; ++c) {
                if (!(side[straddlers[j]] & (1u << c))) continue;
                ++fresh_count[c];
                const Aabb& box = straddler_bounds[2 * j + std::size_t(c)];
                for (int axis = 0; axis < 3; ++axis) flat_fresh[c][axis] += box.lo[axis] == box.hi[axis];
            }
    } else {
        fresh_count = {straddler_count, straddler_count};
        for (int axis = 0; axis < 3; ++axis) {
            // Flat straddlers: all flat triangles (one event each) less the one-sided ones.
            const std::size_t flat_all = 2 * n - node.events[axis].size();
            flat_fresh[0][axis] = flat_fresh[1][axis] = flat_all - one_sided.flat[0][axis] - one_sided.flat[1][axis];
        }
    }

    // Sizes: triangles per child, and per child and axis all events and the fresh ones (those
    // sorted and merged in: perfect splits only).
    std::array<bool, 2> lists{};
    std::array<std::array<std::size_t, 3>, 2> fresh_size{}, total{};
    std::size_t fresh_total = 0, sort_size = 0;
    std::array<NodeWork, 2> child;
    for (int c = 0; c < 2; ++c) {
        const std::size_t size = kept_count[c] + fresh_count[c];
        lists[c] = children_may_split && size > options_.leaf_triangles;
        child[c].cell = cells[c];
        child[c].prims = child_prims[c].first(size);
        child[c].flat_axes = child_flat[c].first(size);
        if (!lists[c]) continue;
        for (int axis = 0; axis < 3; ++axis) {
            total[c][axis] = 2 * size - one_sided.flat[c][axis] - flat_fresh[c][axis];
            if (!perfect) continue;
            fresh_size[c][axis] = 2 * fresh_count[c] - flat_fresh[c][axis];
            fresh_total += fresh_size[c][axis];
            sort_size = std::max(sort_size, fresh_size[c][axis]);
        }
        // One slot of slack after each list: the branch-free filter below may write one past.
        const std::span<Event> all = scratch.kept.allocate<Event>(total[c][0] + total[c][1] + total[c][2] + 3);
        for (std::size_t axis = 0, at = 0; axis < 3; at += total[c][axis++] + 1)
            child[c].events[axis] = all.subspan(at, total[c][axis]);
    }

    // The straddlers follow the one-sided triangles in each child that takes them. dest[i][c]
    // is the index in child c << 2 | 1 when that child takes the triangle's events from the
    // node's lists, 0 when not (the other side, or fresh events).
    std::array<std::uint32_t, 2> next = kept_count;
    for (std::size_t j = 0; j < straddler_count; ++j) {
        const std::uint32_t i = straddlers[j];
        for (unsigned c = 0; c < 2; ++c) {
            if (!(side[i] & (1u << c))) continue;
            const std::uint32_t index = next[c]++;
            child[c].prims[index] = node.prims[i];
            if (perfect) {
                child[c].flat_axes[index] = flat_axes_of(straddler_bounds[2 * j + c]);
            } else {
                child[c].flat_axes[index] = node.flat_axes[i];
                dest[i][c] = index << 2 | 1u;
            }
        }
    }

    // Per axis and child: the events taken from the node's list, filtered in order. On the
    // split axis, the events below the plane go only below and those above only above, and
    // without perfect splits the straddlers' new ends and starts at the plane go in between;
    // with perfect splits, the fresh events are written, sorted and merged in front.
    const std::span<Event> fresh_space = scratch.temp.allocate<Event>(fresh_total);
    const bool parallel = parallel_axes(n);
    const std::span<Event> sort_space = scratch.temp.allocate<Event>((parallel ? 3 : 1) * sort_size);
    const std::array<std::uint32_t, 2> keep{lists[0], lists[1]};
    for_each_axis(parallel, [&](int axis) {
        Event sink[2];  // where a child without lists gets its events
        std::array<Event*, 2> out{};
        for (int c = 0; c < 2; ++c) out[c] = lists[c] ? child[c].events[axis].data() + fresh_size[c][axis] : sink;
        const std::span<const Event> events = node.events[axis];
        if (axis != k) {
            filter_events<2>(events, dest, keep, out);
        } else {
            // Below: events before the plane, ends on it; [straddlers' ends]; planars on it.
            filter_events<0>(events.first(first_planar), dest, keep, out);
            if (!perfect && lists[0])
                for (std::size_t j = 0; j < straddler_count; ++j)
                    *out[0]++ = Event::make(p, std::uint32_t(kept_count[0] + j), EventType::end);
            filter_events<0>(events.subspan(first_planar, first_start - first_planar), dest, keep, out);
            // Above: planars on the plane; [straddlers' starts]; starts on it, events after it.
            filter_events<1>(events.subspan(first_planar, first_start - first_planar), dest, keep, out);
            if (!perfect && lists[1])
                for (std::size_t j = 0; j < straddler_count; ++j)
                    *out[1]++ = Event::make(p, std::uint32_t(kept_count[1] + j), EventType::start);
            filter_events<1>(events.subspan(first_start), dest, keep, out);
        }
        if (!perfect || straddler_count == 0) return;
        const std::span<Event> sort_scratch = sort_space.subspan((parallel ? axis : 0) * sort_size, sort_size);
        std::size_t fresh_at = 0;
        for (int c = 0; c < 2; ++c) {
            for (int a = 0; a < axis; ++a) fresh_at += fresh_size[c][a];
            const std::span<Event> fresh = fresh_space.subspan(fresh_at, fresh_size[c][axis]);
            for (int a = axis; a < 3; ++a) fresh_at += fresh_size[c][a];
            if (fresh.empty()) continue;
            // The straddlers this child keeps, in the order their indices were given.
            std::size_t j = 0;
            auto box_of = [&](std::size_t) -> const Aabb& {
                while (!(side[straddlers[j]] & (1u << c))) ++j;
                return straddler_bounds[2 * j++ + std::size_t(c)];
            };
            write_events(fresh_count[c], box_of, axis, std::uint32_t(kept_count[c]), flat_fresh[c][axis], fresh);
            sort_events(fresh, sort_scratch);
            merge_into_tail(fresh, child[c].events[axis]);
        }
    });
    scratch.temp.release(temp_mark);
    return child;
}

}  // namespace trident::kd
