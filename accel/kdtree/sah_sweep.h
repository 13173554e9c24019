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
#include <algorithm>
#include <bit>
#include <cstddef>
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

/// The candidate's area-weighted counts as ordered bits, SweepBest::kNone when it makes no progress.
inline std::uint64_t candidate_key(const SweepSetup& s, float position, double below_area, double above_area,
                                   std::int64_t nb, std::int64_t na) {
    double weighted = below_area * double(nb) + above_area * double(na);
    if (nb * na == 0) [[unlikely]] {
        // A child equal to the node (the other one flat and empty) makes no progress.
        if ((nb == 0 && position == s.lo) || (na == 0 && position == s.hi)) return SweepBest::kNone;
        weighted *= s.empty_scale;  // pbrt applies the bonus to the intersection term only
    }
    return std::bit_cast<std::uint64_t>(weighted);
}

inline void consider(const SweepSetup& s, float position, double below_area, double above_area, std::int64_t nb,
                     std::int64_t na, std::uint64_t tag, SweepBest& best) {
    const std::uint64_t key = candidate_key(s, position, below_area, above_area, nb, na);
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

/// The sweep one event at a time: the reference, and the sweep where AVX-512 is missing.
inline SweepBest sweep_events_scalar(std::span<const Event> events, const SweepSetup& setup) {
    detail::SweepState state;
    for (std::size_t i = 0; i < events.size(); ++i) detail::sweep_step(events, i, setup, state);
    return state.best;
}

#if TRIDENT_KD_AVX512
namespace detail {

/// Lane j of x moved to lane j + Shift, zeros below.
template <int Shift>
inline __m256i lanes_up(__m256i x) {
    return _mm256_alignr_epi32(x, _mm256_setzero_si256(), 8 - Shift);
}
inline __m256i inclusive_sum(__m256i x) {
    x = _mm256_add_epi32(x, lanes_up<1>(x));
    x = _mm256_add_epi32(x, lanes_up<2>(x));
    return _mm256_add_epi32(x, lanes_up<4>(x));
}
inline __m256i inclusive_max(__m256i x) {
    x = _mm256_max_epu32(x, lanes_up<1>(x));
    x = _mm256_max_epu32(x, lanes_up<2>(x));
    return _mm256_max_epu32(x, lanes_up<4>(x));
}
// GCC 12 warns that the plain forms of some intrinsics read an undefined vector
// (-Wmaybe-uninitialized); their zero-masked forms with every lane set are the same instructions.
inline __m256i narrow(__m512i x) { return _mm512_maskz_cvtepi64_epi32(0xFF, x); }
inline std::uint64_t min_lane(__m512i x) {
    x = _mm512_maskz_min_epu64(0xFF, x, _mm512_maskz_shuffle_i64x2(0xFF, x, x, _MM_SHUFFLE(1, 0, 3, 2)));
    x = _mm512_maskz_min_epu64(0xFF, x, _mm512_maskz_shuffle_i64x2(0xFF, x, x, _MM_SHUFFLE(2, 3, 0, 1)));
    x = _mm512_maskz_min_epu64(0xFF, x, _mm512_maskz_shuffle_epi32(0xFFFF, x, _MM_PERM_BADC));
    return std::uint64_t(_mm_cvtsi128_si64(_mm512_maskz_extracti32x4_epi32(0xF, x, 0)));
}
inline __m256i last_lane(__m256i x) { return _mm256_permutexvar_epi32(_mm256_set1_epi32(7), x); }

/// Eight candidates' keys as candidate_key computes them (the same double operations in the same
/// order, so the same bits), all ones where a candidate makes no progress.
inline __m512i lane_keys(const SweepSetup& s, __m256 position, __m512d below_area, __m512d above_area, __m256i nb,
                         __m256i na) {
    const __m512d weighted = _mm512_add_pd(_mm512_mul_pd(below_area, _mm512_maskz_cvtepu32_pd(0xFF, nb)),
                                           _mm512_mul_pd(above_area, _mm512_maskz_cvtepu32_pd(0xFF, na)));
    const __mmask8 below_empty = _mm256_cmpeq_epi32_mask(nb, _mm256_setzero_si256());
    const __mmask8 above_empty = _mm256_cmpeq_epi32_mask(na, _mm256_setzero_si256());
    const __mmask8 no_progress = (below_empty & _mm256_cmp_ps_mask(position, _mm256_set1_ps(s.lo), _CMP_EQ_OQ)) |
                                 (above_empty & _mm256_cmp_ps_mask(position, _mm256_set1_ps(s.hi), _CMP_EQ_OQ));
    const __m512i key = _mm512_castpd_si512(
        _mm512_mask_mul_pd(weighted, below_empty | above_empty, weighted, _mm512_set1_pd(s.empty_scale)));
    return _mm512_mask_mov_epi64(key, no_progress, _mm512_set1_epi64(-1));
}

/// Candidates in the lanes of `consider`, kept per lane when strictly better (a candidate making
/// no progress has the key of none, so it never is).
inline void consider_lanes(const SweepSetup& s, __mmask8 consider, __m256 position, __m512d below_area,
                           __m512d above_area, __m256i nb, __m256i na, __m512i tags, __m512i& best_key,
                           __m512i& best_tag) {
    const __m512i key = lane_keys(s, position, below_area, above_area, nb, na);
    const __mmask8 better = _mm512_mask_cmplt_epu64_mask(consider, key, best_key);
    best_key = _mm512_mask_mov_epi64(best_key, better, key);
    best_tag = _mm512_mask_mov_epi64(best_tag, better, tags);
}

}  // namespace detail

/// The sweep eight events at a time, the same result as sweep_events_scalar bit for bit. The
/// running counts are prefix sums over the lanes; a group's counts at its first event are a prefix
/// maximum, the counts growing along the list. Each lane keeps its best candidate (the earliest of
/// equal ones); the lowest tag among the lanes' best wins a tie, as the sequential sweep has it.
inline SweepBest sweep_events_avx512(std::span<const Event> events, const SweepSetup& s) {
    static_assert(sizeof(Event) == 8 && offsetof(Event, position) == 0);
    const std::size_t n = events.size();
    const void* const data = events.data();
    // Past the end: all ones, a NaN position that equals no event's and a type that counts nothing.
    auto load = [&](std::size_t i) {
        const __mmask8 valid = i < n ? __mmask8(n - i >= 8 ? 0xFF : (1u << (n - i)) - 1u) : __mmask8(0);
        return _mm512_mask_loadu_epi64(_mm512_set1_epi64(-1), valid,
                                       static_cast<const std::uint64_t*>(data) + std::min(i, n));
    };
    const __m256i zero = _mm256_setzero_si256(), one = _mm256_set1_epi32(1), type_mask = _mm256_set1_epi32(3);
    const __m256i triangles = _mm256_set1_epi32(std::int32_t(s.triangles));
    const __m512d side = _mm512_set1_pd(s.side), below_base = _mm512_set1_pd(s.below_base),
                  above_base = _mm512_set1_pd(s.above_base);
    __m256i before = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);  // events before each lane
    __m512i tags = _mm512_setr_epi64(0, 2, 4, 6, 8, 10, 12, 14);
    // The counts before the chunk, in every lane.
    __m256i not_above = zero, planar = zero, below_at_group = zero, planar_at_group = zero;
    __m256i previous_bits = _mm256_set1_epi32(-1);
    __m512i best_key = _mm512_set1_epi64(-1), best_tag = _mm512_setzero_si512();
    __m512i chunk = load(0);
    for (std::size_t i = 0; i < n; i += 8) {
        const __m512i next_chunk = load(i + 8);
        const __m256i bits = detail::narrow(chunk);
        const __m256i type = _mm256_and_si256(detail::narrow(_mm512_maskz_srli_epi64(0xFF, chunk, 32)), type_mask);
        const __mmask8 valid = _mm256_cmpneq_epi32_mask(type, type_mask);
        const __mmask8 is_start = _mm256_cmpeq_epi32_mask(type, _mm256_set1_epi32(2));
        const __mmask8 is_planar = _mm256_cmpeq_epi32_mask(type, one);
        const __mmask8 group_starts = _mm256_cmpneq_epi32_mask(bits, _mm256_alignr_epi32(bits, previous_bits, 7));
        const __mmask8 group_ends =
            valid & _mm256_cmpneq_epi32_mask(bits, _mm256_alignr_epi32(detail::narrow(next_chunk), bits, 1));

        const __m256i not_above_step = _mm256_maskz_mov_epi32(valid & ~is_start, one);
        const __m256i not_above_after = _mm256_add_epi32(not_above, detail::inclusive_sum(not_above_step));
        const __m256i above = _mm256_sub_epi32(triangles, not_above_after);
        // Planar events are rare: without any in the chunk or in a group left open by the previous
        // chunk, every lane has the counts before it and none in the plane.
        __m256i planar_before = planar, in_plane = zero;
        const bool planars = (is_planar | _mm256_cmpneq_epi32_mask(planar, planar_at_group)) != 0;
        if (planars) [[unlikely]] {
            const __m256i planar_step = _mm256_maskz_mov_epi32(is_planar, one);
            const __m256i planar_after = _mm256_add_epi32(planar, detail::inclusive_sum(planar_step));
            planar_before = _mm256_sub_epi32(planar_after, planar_step);
            const __m256i planar_at = _mm256_max_epu32(
                planar_at_group, detail::inclusive_max(_mm256_maskz_mov_epi32(group_starts, planar_before)));
            in_plane = _mm256_sub_epi32(planar_after, planar_at);
            planar = detail::last_lane(planar_after);
            planar_at_group = detail::last_lane(planar_at);
        }
        // Every event is an end, a planar or a start: below = events + planars - not above.
        const __m256i below_before = _mm256_sub_epi32(_mm256_add_epi32(before, planar_before),
                                                      _mm256_sub_epi32(not_above_after, not_above_step));
        const __m256i nb =
            _mm256_max_epu32(below_at_group, detail::inclusive_max(_mm256_maskz_mov_epi32(group_starts, below_before)));

        const __m256 position = _mm256_castsi256_ps(bits);
        const __m512d scaled = _mm512_mul_pd(_mm512_maskz_cvtps_pd(0xFF, position), side);
        const __m512d below_area = _mm512_add_pd(below_base, scaled), above_area = _mm512_sub_pd(above_base, scaled);
        detail::consider_lanes(s, group_ends, position, below_area, above_area, nb, _mm256_add_epi32(above, in_plane),
                               tags, best_key, best_tag);
        if (planars) [[unlikely]] {
            const __mmask8 with_planars = group_ends & _mm256_cmpneq_epi32_mask(in_plane, zero);
            if (with_planars)
                detail::consider_lanes(s, with_planars, position, below_area, above_area,
                                       _mm256_add_epi32(nb, in_plane), above,
                                       _mm512_or_si512(tags, _mm512_set1_epi64(1)), best_key, best_tag);
        }

        not_above = detail::last_lane(not_above_after);
        below_at_group = detail::last_lane(nb);
        previous_bits = bits;
        chunk = next_chunk;
        before = _mm256_add_epi32(before, _mm256_set1_epi32(8));
        tags = _mm512_add_epi64(tags, _mm512_set1_epi64(16));
    }
    SweepBest best;
    best.key = detail::min_lane(best_key);
    if (best.found()) {
        const __mmask8 winners = _mm512_cmpeq_epi64_mask(best_key, _mm512_set1_epi64(std::int64_t(best.key)));
        best.tag = detail::min_lane(_mm512_mask_mov_epi64(_mm512_set1_epi64(-1), winners, best_tag));
    }
    return best;
}
#endif

/// Whether the searches below may take the portable build's AVX-512 forms, compiled in its
/// 16-lane kernel file (kd_sweep_kernels.cpp): the CPU has AVX-512 and TRIDENT_ISA allows it.
/// False in any other build, whose searches follow its own -march. Asked once per build
/// (SahBuilder), not per search: it reads cpuid's answer and the cap.
bool avx512_file_searches_runnable();

#if TRIDENT_PORTABLE_BUILD && !TRIDENT_KD_AVX512
SweepBest sweep_events_avx512_file(std::span<const Event> events, const SweepSetup& setup);
#endif

/// The cheapest plane among the events of one axis, sorted in the sweep order; none found when
/// every candidate would leave a child equal to the node. `avx512_file`: what
/// avx512_file_searches_runnable() answered.
inline SweepBest sweep_events(std::span<const Event> events, const SweepSetup& setup,
                              [[maybe_unused]] bool avx512_file = false) {
#if TRIDENT_KD_AVX512
    return sweep_events_avx512(events, setup);
#else
#if TRIDENT_PORTABLE_BUILD
    if (avx512_file) return sweep_events_avx512_file(events, setup);
#endif
    return sweep_events_scalar(events, setup);
#endif
}

/// The triangles of a small node on one axis, as their boxes' ends (lo == hi where a box is flat
/// on the axis), padded to Capacity with lo = +inf, hi = -inf, which no plane counts. With
/// Capacity 8, the 16 ends are one 64-byte line: one AVX-512 vector of candidate planes.
template <std::size_t Capacity>
struct alignas(64) BoxEnds {
    float lo[Capacity];
    float hi[Capacity];
};

/// The plane a sweep finds, as a position rather than an event.
struct CountedPlane {
    std::uint64_t key = SweepBest::kNone;
    float position = 0.0f;
    bool planars_below = false;

    bool found() const { return key != SweepBest::kNone; }
    double weighted() const { return std::bit_cast<double>(key); }
};

/// count_planes one candidate at a time: the reference, and the search where AVX-512 is missing.
template <std::size_t Capacity>
CountedPlane count_planes_scalar(const BoxEnds<Capacity>& ends, std::size_t count, const SweepSetup& s) {
    CountedPlane best;
    auto take = [&](std::uint64_t key, float position, bool planars_below) {
        const bool better =
            key < best.key ||
            (key == best.key && key != SweepBest::kNone &&
             (position < best.position || (position == best.position && !planars_below && best.planars_below)));
        if (better) best = {key, position + 0.0f, planars_below};  // +0 for -0, as events store it
    };
    auto evaluate = [&](float position) {
        std::int32_t nb = 0, na = 0, in_plane = 0;
        for (std::size_t j = 0; j < count; ++j) {
            nb += ends.lo[j] < position;
            na += ends.hi[j] > position;
            in_plane += (ends.lo[j] == position) & (ends.hi[j] == position);
        }
        const double scaled = double(position) * s.side;
        const double below_area = s.below_base + scaled, above_area = s.above_base - scaled;
        take(detail::candidate_key(s, position, below_area, above_area, nb, na + in_plane), position, false);
        if (in_plane > 0)
            take(detail::candidate_key(s, position, below_area, above_area, nb + in_plane, na), position, true);
    };
    for (std::size_t i = 0; i < count; ++i) {
        evaluate(ends.lo[i]);
        if (ends.hi[i] != ends.lo[i]) evaluate(ends.hi[i]);
    }
    return best;
}

#if TRIDENT_KD_AVX512
namespace detail {

/// Eight candidates' keys (lane_keys), all ones too where a candidate is not `valid`.
inline __m512i candidate_keys(const SweepSetup& s, __mmask8 valid, __m256 position, __m256i nb, __m256i na) {
    const __m512d scaled = _mm512_mul_pd(_mm512_maskz_cvtps_pd(0xFF, position), _mm512_set1_pd(s.side));
    const __m512d below_area = _mm512_add_pd(_mm512_set1_pd(s.below_base), scaled);
    const __m512d above_area = _mm512_sub_pd(_mm512_set1_pd(s.above_base), scaled);
    return _mm512_mask_mov_epi64(_mm512_set1_epi64(-1), valid, lane_keys(s, position, below_area, above_area, nb, na));
}

}  // namespace detail

/// count_planes with the 16 box ends of up to 8 triangles as one vector of candidates: each
/// triangle adds its counts to all of them at once; the keys of the ends and of the variants with
/// planar triangles below are computed eight at a time, and ties (equal keys) are resolved as the
/// scalar search resolves them.
inline CountedPlane count_planes_avx512(const BoxEnds<8>& ends, std::size_t count, const SweepSetup& s) {
    constexpr float kInfinityPosition = std::numeric_limits<float>::infinity();
    const __m512 candidates = _mm512_load_ps(ends.lo);  // lanes 0-7 the lower ends, 8-15 the upper ones
    const __mmask16 triangles = __mmask16((1u << count) - 1u);
    const __mmask16 valid = __mmask16(triangles | triangles << 8);
    const __m512i one = _mm512_set1_epi32(1);
    __m512i nb = _mm512_setzero_si512(), na = _mm512_setzero_si512(), in_plane = _mm512_setzero_si512();
    for (std::size_t j = 0; j < count; ++j) {
        const __m512 lo = _mm512_set1_ps(ends.lo[j]), hi = _mm512_set1_ps(ends.hi[j]);
        nb = _mm512_mask_add_epi32(nb, _mm512_cmp_ps_mask(candidates, lo, _CMP_GT_OQ), nb, one);
        na = _mm512_mask_add_epi32(na, _mm512_cmp_ps_mask(candidates, hi, _CMP_LT_OQ), na, one);
        if (ends.lo[j] == ends.hi[j])
            in_plane = _mm512_mask_add_epi32(in_plane, _mm512_cmp_ps_mask(candidates, lo, _CMP_EQ_OQ), in_plane, one);
    }
    const __mmask16 with_planars = _mm512_mask_cmpneq_epi32_mask(valid, in_plane, _mm512_setzero_si512());
    // keys[h] for the candidates of half h (0: lower ends, 1: upper ends), planar triangles above;
    // keys[2 + h] with them below, where there are any.
    __m512i keys[4];
    for (int h = 0; h < 2; ++h) {
        // The masked forms: GCC 12 warns that the plain casts and extracts read an undefined vector.
        auto half = [h](__m512i x) {
            return h == 0 ? _mm512_maskz_extracti64x4_epi64(0xF, x, 0) : _mm512_maskz_extracti64x4_epi64(0xF, x, 1);
        };
        const __m256 position = _mm256_castsi256_ps(half(_mm512_castps_si512(candidates)));
        const __m256i nb_h = half(nb), na_h = half(na), in_h = half(in_plane);
        const auto valid_h = __mmask8(valid >> (8 * h)), planars_h = __mmask8(with_planars >> (8 * h));
        keys[h] = detail::candidate_keys(s, valid_h, position, nb_h, _mm256_add_epi32(na_h, in_h));
        keys[2 + h] = planars_h ? detail::candidate_keys(s, planars_h, position, _mm256_add_epi32(nb_h, in_h), na_h)
                                : _mm512_set1_epi64(-1);
    }
    CountedPlane best;
    best.key = detail::min_lane(_mm512_maskz_min_epu64(0xFF, _mm512_maskz_min_epu64(0xFF, keys[0], keys[1]),
                                                       _mm512_maskz_min_epu64(0xFF, keys[2], keys[3])));
    if (!best.found()) return best;
    const __m512i key = _mm512_set1_epi64(std::int64_t(best.key));
    // The winners: lower position first, then planar triangles above.
    const __mmask16 above_winners =
        __mmask16(_mm512_cmpeq_epu64_mask(keys[0], key) | unsigned(_mm512_cmpeq_epu64_mask(keys[1], key)) << 8);
    const __mmask16 below_winners =
        __mmask16(_mm512_cmpeq_epu64_mask(keys[2], key) | unsigned(_mm512_cmpeq_epu64_mask(keys[3], key)) << 8);
    alignas(64) float positions[16];  // the candidates by lane: lo, then hi
    _mm512_store_ps(positions, candidates);
    best.position = kInfinityPosition;
    for (unsigned winners = above_winners | below_winners; winners != 0; winners &= winners - 1)
        best.position = std::min(best.position, positions[std::countr_zero(winners)]);
    best.position += 0.0f;
    const __mmask16 at_position = _mm512_cmp_ps_mask(candidates, _mm512_set1_ps(best.position), _CMP_EQ_OQ);
    best.planars_below = (above_winners & at_position) == 0;
    return best;
}
#endif

#if TRIDENT_PORTABLE_BUILD && !TRIDENT_KD_AVX512
CountedPlane count_planes_avx512_file(const BoxEnds<8>& ends, std::size_t count, const SweepSetup& setup);
#endif

/// The plane sweep_events finds over these triangles' events, found without events for nodes of a
/// few triangles: every box end is a candidate, and its counts are counted directly (below: the
/// boxes starting before it, above: those ending after it, in the plane: the flat ones on it).
/// The same candidate weights in the same double operations give the same bits; a tie goes to the
/// lower position and, at one position, to the planar triangles above, as the sweep's event order
/// has it. `count` triangles, each one's ends lo[i] and hi[i]; `avx512_file` as sweep_events().
inline CountedPlane count_planes(const BoxEnds<8>& ends, std::size_t count, const SweepSetup& s,
                                 [[maybe_unused]] bool avx512_file = false) {
#if TRIDENT_KD_AVX512
    return count_planes_avx512(ends, count, s);
#else
#if TRIDENT_PORTABLE_BUILD
    if (avx512_file) return count_planes_avx512_file(ends, count, s);
#endif
    return count_planes_scalar(ends, count, s);
#endif
}

}  // namespace trident::kd
