// The kd-tree's parts on their own: the packed node, event sorting and merging, the SAH sweep,
// and clipping a triangle to a box for perfect splits.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "accel/kdtree/clip_triangle.h"
#include "accel/kdtree/kd_event.h"
#include "accel/kdtree/kd_node.h"
#include "accel/kdtree/sah_sweep.h"

using namespace trident;
using kd::Event;
using kd::EventType;

TEST_CASE("an interior node keeps its axis, split, first child and empty children; a leaf its count and offset") {
    for (int axis = 0; axis < 3; ++axis)
        for (const bool below_empty : {false, true})
            for (const bool above_empty : {false, true}) {
                const KdNode node = KdNode::interior(axis, -1.25f, KdNode::kMaxIndex - 1, below_empty, above_empty);
                CHECK_FALSE(node.is_leaf());
                CHECK(node.axis() == axis);
                CHECK(node.split() == -1.25f);
                CHECK(node.below_child() == KdNode::kMaxIndex - 1);
                CHECK(node.above_child() == KdNode::kMaxIndex);
                CHECK(node.below_empty() == below_empty);
                CHECK(node.above_empty() == above_empty);
            }
    const KdNode leaf = KdNode::leaf(0xFFFFFFFFu, KdNode::kMaxIndex);
    CHECK(leaf.is_leaf());
    CHECK_FALSE(leaf.is_empty_leaf());
    CHECK(leaf.triangle_count() == 0xFFFFFFFFu);
    CHECK(leaf.triangle_offset() == KdNode::kMaxIndex);
    CHECK(KdNode::leaf(0, 0).is_empty_leaf());
    CHECK_FALSE(KdNode::interior(0, 0.0f, 0).is_empty_leaf());
}

TEST_CASE("an index that does not fit in 28 bits is refused with a clear error") {
    CHECK(KdNode::kMaxIndex == (1u << 28) - 1);
    CHECK_THROWS_AS(KdNode::interior(0, 0.0f, std::size_t(KdNode::kMaxIndex) + 1), std::length_error);
    CHECK_THROWS_AS(KdNode::leaf(1, std::size_t(KdNode::kMaxIndex) + 1), std::length_error);
    CHECK_THROWS_AS(KdNode::leaf(1, std::size_t(1) << 32), std::length_error);
    CHECK_THROWS_WITH(KdNode::interior(2, 0.0f, std::size_t(1) << 29),
                      doctest::Contains("exceeds the 268435456 entries a KdNode can index"));
}

TEST_CASE("events sort by position, then ends before planars before starts, by radix or comparison") {
    for (const std::size_t count : {std::size_t(100), std::size_t(10000)}) {  // below and above the radix threshold
        std::mt19937 rng{std::uint32_t(count)};
        std::uniform_int_distribution<int> coarse(-20, 20), type(0, 2);
        // Ends first, then planars, then starts, as the builder writes them for the radix sort.
        std::vector<Event> events{Event::make(0.0f, 8, EventType::end)};  // -0 and +0 must sort together
        for (int t = 0; t < 3; ++t)
            for (std::size_t i = 0; i < count; ++i)
                if (type(rng) == t)
                    events.push_back(Event::make(float(coarse(rng)) * 0.5f, std::uint32_t(i), EventType(t)));
        events.push_back(Event::make(-0.0f, 7, EventType::start));
        std::vector<Event> scratch(events.size());
        kd::sort_events(events, scratch);
        CHECK(std::is_sorted(events.begin(), events.end(), kd::event_before));
        for (std::size_t i = 1; i < events.size(); ++i)
            if (events[i].position == events[i - 1].position) {
                CHECK(events[i].type() >= events[i - 1].type());
                CHECK(std::bit_cast<std::uint32_t>(events[i].position) ==
                      std::bit_cast<std::uint32_t>(events[i - 1].position));
            }
    }
}

TEST_CASE("merging fresh events in front of the kept ones stored in the tail gives one sorted list") {
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> coarse(0, 30), type(0, 2);
    auto random_sorted = [&](std::size_t n) {
        std::vector<Event> v;
        for (std::size_t i = 0; i < n; ++i)
            v.push_back(Event::make(float(coarse(rng)), std::uint32_t(i), EventType(type(rng))));
        std::sort(v.begin(), v.end(), kd::event_before);
        return v;
    };
    for (const auto& [fresh_count, kept_count] :
         {std::pair{0, 5}, std::pair{5, 0}, std::pair{40, 60}, std::pair{60, 3}}) {
        const std::vector<Event> fresh = random_sorted(std::size_t(fresh_count));
        const std::vector<Event> kept = random_sorted(std::size_t(kept_count));
        std::vector<Event> out(fresh.size() + kept.size());
        std::copy(kept.begin(), kept.end(), out.begin() + std::ptrdiff_t(fresh.size()));
        kd::merge_into_tail(fresh, out);
        CHECK(std::is_sorted(out.begin(), out.end(), kd::event_before));
        std::vector<Event> expected = fresh;
        expected.insert(expected.end(), kept.begin(), kept.end());
        auto key = [](const Event& e) { return std::pair{e.position, e.prim_type}; };
        std::vector<std::pair<float, std::uint32_t>> got_keys, expected_keys;
        for (const Event& e : out) got_keys.push_back(key(e));
        for (const Event& e : expected) expected_keys.push_back(key(e));
        std::sort(got_keys.begin(), got_keys.end());
        std::sort(expected_keys.begin(), expected_keys.end());
        CHECK(got_keys == expected_keys);
    }
}

TEST_CASE("a triangle clipped to a box keeps the bounds of its part inside the box") {
    const Aabb box{{0, 0, 0}, {1, 1, 1}};
    SUBCASE("inside: its own bounds") {
        const Triangle tri{{0.1f, 0.2f, 0.3f}, {0.9f, 0.2f, 0.3f}, {0.5f, 0.8f, 0.7f}};
        const auto b = kd::clipped_triangle_bounds(tri, box);
        REQUIRE(b);
        CHECK(b->lo == tri.bounds().lo);
        CHECK(b->hi == tri.bounds().hi);
    }
    SUBCASE("outside although its bounding box overlaps: nothing") {
        // The diagonal x + y = 2.5 misses the box while its bounds reach into it.
        const Triangle tri{{2.5f, 0.0f, 0.5f}, {0.0f, 2.5f, 0.5f}, {2.5f, 2.5f, 0.5f}};
        CHECK(tri.bounds().lo.x < 1.0f);
        CHECK_FALSE(kd::clipped_triangle_bounds(tri, box));
    }
    SUBCASE("straddling a face: cut at the face, exactly") {
        const Triangle tri{{0.5f, 0.5f, 0.5f}, {1.5f, 0.5f, 0.5f}, {1.5f, 0.75f, 0.5f}};
        const auto b = kd::clipped_triangle_bounds(tri, box);
        REQUIRE(b);
        CHECK(b->lo.x == 0.5f);
        CHECK(b->hi.x == 1.0f);
        CHECK(b->hi.y == 0.625f);  // where the long edge leaves the box at x = 1
    }
    SUBCASE("touching a face from outside: the touching edge, flat") {
        const Triangle tri{{1.0f, 0.2f, 0.2f}, {1.0f, 0.6f, 0.2f}, {2.0f, 0.4f, 0.4f}};
        const auto b = kd::clipped_triangle_bounds(tri, box);
        REQUIRE(b);
        CHECK(b->lo.x == 1.0f);
        CHECK(b->hi.x == 1.0f);
    }
}

TEST_CASE("clipped bounds contain every point of the triangle that lies in the box") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> coord(-1.0f, 2.0f), unit(0.0f, 1.0f);
    const Aabb box{{0, 0, 0}, {1, 1, 1}};
    int clipped_away = 0;
    for (int t = 0; t < 300; ++t) {
        const Triangle tri{{coord(rng), coord(rng), coord(rng)},
                           {coord(rng), coord(rng), coord(rng)},
                           {coord(rng), coord(rng), coord(rng)}};
        const auto b = kd::clipped_triangle_bounds(tri, box);
        if (b) {
            CHECK(box.contains(*b));
            CHECK(tri.bounds().contains(*b));
        }
        for (int s = 0; s < 300; ++s) {
            float u = unit(rng), v = unit(rng);
            if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
            const Vec3f p = tri.a + (tri.b - tri.a) * u + (tri.c - tri.a) * v;
            if (!box.contains(p)) continue;
            REQUIRE(b);
            // p itself carries float rounding, up to an ulp or two outside the exact triangle.
            const Vec3f slack{1e-6f};
            CHECK(Aabb{b->lo - slack, b->hi + slack}.contains(p));
        }
        clipped_away += !b;
    }
    CHECK(clipped_away > 0);  // the sample covers triangles that miss the box
}

namespace {

/// The plane the sweep picks for triangles given as [lo, hi] intervals on the axis, in the cell
/// [0, cell_hi] whose faces across the axis have half area 1 and sides scale by 1.
/// Appends the events of triangle i, whose bounds on the axis are [lo, hi]: one planar event when
/// they are flat, else an end and a start.
void add_events(std::vector<Event>& events, float lo, float hi, std::uint32_t i) {
    if (lo == hi) {
        events.push_back(Event::make(lo, i, EventType::planar));
    } else {
        events.push_back(Event::make(hi, i, EventType::end));
        events.push_back(Event::make(lo, i, EventType::start));
    }
}

std::pair<float, bool> sweep_pick(const std::vector<std::pair<float, float>>& intervals, float cell_hi) {
    std::vector<Event> events;
    for (std::uint32_t i = 0; i < intervals.size(); ++i) add_events(events, intervals[i].first, intervals[i].second, i);
    std::sort(events.begin(), events.end(), kd::event_before);
    const kd::SweepSetup setup{std::int64_t(intervals.size()), 1.0, 1.0 + double(cell_hi), 1.0, 0.0f, cell_hi, 0.5};
    const kd::SweepBest best = kd::sweep_events(events, setup);
    REQUIRE(best.found());
    return {events[best.tag >> 1].position, (best.tag & 1u) != 0};
}

}  // namespace

TEST_CASE("the sweep picks the cheapest plane and sends planar triangles to the cheaper side") {
    // Two triangles apart: the gap's two ends cost the same, the earlier wins.
    CHECK(sweep_pick({{0, 1}, {3, 4}}, 4).first == 1.0f);
    // A triangle in the plane x = 2 between two others: splitting there is cheapest; both sides
    // cost the same for it, so it goes above (Wald and Havran's tie rule).
    CHECK(sweep_pick({{0, 1}, {2, 2}, {3, 4}}, 4) == std::pair{2.0f, false});
    // With a larger cell above, the planar triangle is cheaper below.
    CHECK(sweep_pick({{0, 1}, {2, 2}, {3, 6}}, 6) == std::pair{2.0f, true});
    // A plane on the cell's face with nothing beyond it makes no progress and is never picked.
    CHECK(sweep_pick({{0, 3}}, 6).first == 3.0f);
    CHECK(sweep_pick({{3, 6}}, 6).first == 3.0f);
}

TEST_CASE("the vector sweep picks the plane and the planar side of the scalar sweep, bit for bit") {
    // Positions on a coarse grid, so that many events share a position (groups of ends, planars and
    // starts), and lists of every length around the vector width; cells on both sides of zero.
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> grid(0, 24);
    std::uniform_int_distribution<int> length(0, 60);
    int compared = 0;
    for (int round = 0; round < 3000; ++round) {
        const int triangles = length(rng);
        const float offset = round % 3 == 0 ? -12.0f : 0.0f;
        std::vector<Event> events;
        for (int i = 0; i < triangles; ++i) {
            int lo = grid(rng), hi = grid(rng);
            if (lo > hi) std::swap(lo, hi);
            if (round % 2 == 0 && i % 3 == 0) hi = lo;  // planars
            add_events(events, float(lo) * 0.5f + offset, float(hi) * 0.5f + offset, std::uint32_t(i));
        }
        std::sort(events.begin(), events.end(), kd::event_before);
        const float lo = offset, hi = 12.0f + offset;
        const double across = 1.0 + double(round % 5), side = 0.5 + double(round % 7);
        const kd::SweepSetup setup{
            std::int64_t(triangles), across - double(lo) * side, across + double(hi) * side, side, lo, hi, 0.5};
        const kd::SweepBest scalar = kd::sweep_events_scalar(events, setup);
        const kd::SweepBest chosen = kd::sweep_events(events, setup);
        CHECK(chosen.key == scalar.key);
        CHECK(chosen.tag == scalar.tag);
        compared += scalar.found();
    }
    CHECK(compared > 2000);
}

TEST_CASE("counting at the box ends picks the event sweep's plane and planar side, bit for bit") {
    // Small nodes (up to 8 triangles) on a coarse grid, so that ends coincide, planar triangles
    // share planes and equal costs tie; cells on both sides of zero, and -0 among the ends.
    std::mt19937 rng(11);
    std::uniform_int_distribution<int> grid(0, 12);
    std::uniform_int_distribution<int> length(1, 8);
    int compared = 0, with_planars = 0;
    for (int round = 0; round < 20000; ++round) {
        const int triangles = length(rng);
        const float offset = round % 3 == 0 ? -3.0f : 0.0f;
        kd::BoxEnds<8> ends;
        std::fill(std::begin(ends.lo), std::end(ends.lo), kInfinity);
        std::fill(std::begin(ends.hi), std::end(ends.hi), -kInfinity);
        std::vector<Event> events;
        for (int i = 0; i < triangles; ++i) {
            int lo = grid(rng), hi = grid(rng);
            if (lo > hi) std::swap(lo, hi);
            if (round % 2 == 0 && i % 3 == 0) hi = lo;  // planars
            float a = float(lo) * 0.5f + offset, b = float(hi) * 0.5f + offset;
            if (a == 0.0f && round % 4 == 0) a = -0.0f;
            if (b == 0.0f && round % 4 == 0) b = -0.0f;
            ends.lo[i] = a;
            ends.hi[i] = b;
            add_events(events, a, b, std::uint32_t(i));
        }
        std::sort(events.begin(), events.end(), kd::event_before);
        const float lo = offset, hi = 6.0f + offset;
        const double across = 1.0 + double(round % 5), side = 0.5 + double(round % 7);
        const kd::SweepSetup setup{
            std::int64_t(triangles), across - double(lo) * side, across + double(hi) * side, side, lo, hi, 0.5};
        const kd::SweepBest swept = kd::sweep_events_scalar(events, setup);
        for (const kd::CountedPlane counted : {kd::count_planes_scalar(ends, std::size_t(triangles), setup),
                                               kd::count_planes(ends, std::size_t(triangles), setup)}) {
            REQUIRE(counted.found() == swept.found());
            if (!swept.found()) continue;
            CHECK(counted.key == swept.key);
            CHECK(std::bit_cast<std::uint32_t>(counted.position) ==
                  std::bit_cast<std::uint32_t>(events[swept.tag >> 1].position));
            CHECK(counted.planars_below == ((swept.tag & 1u) != 0));
        }
        compared += swept.found();
        with_planars += swept.found() && (swept.tag & 1u) != 0;
    }
    CHECK(compared > 15000);
    CHECK(with_planars > 100);  // the planar-below variant is exercised
}
