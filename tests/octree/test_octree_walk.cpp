// The parametric walk (Revelles et al.) on its own: which children a line crosses and in which
// order, checked against slab intervals computed directly in double.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "accel/octree/octree_walk.h"
#include "octree/octree_test_support.h"

using namespace trident;
using testing::line_interval;

namespace {

/// The real children the walk visits, with their slabs, starting from a node's slabs.
struct WalkedChild {
    unsigned child;
    NodeSlabs slabs;
};

std::vector<WalkedChild> walk_children(const OctreeWalkRay& walk, const NodeSlabs& slabs, const OctreeCube& cell) {
    std::vector<WalkedChild> out;
    const Vec3f tm = slab_midpoints(walk, slabs, cell);
    for (unsigned c = first_child(slabs, tm); c < 8;) {
        const NodeSlabs child = child_slabs(c, slabs, tm);
        out.push_back({c ^ walk.mirror, child});
        c = next_child(c, child);
    }
    return out;
}

std::pair<double, double> cell_interval(const Ray& ray, const OctreeCube& cell) {
    const Vec3d lo(cell.lo);
    return line_interval(ray, lo, lo + Vec3d(double(cell.size)));
}

/// The children whose cells the line crosses for longer than `min_length`, by entry.
std::vector<unsigned> crossed_children(const Ray& ray, const OctreeCube& cell, double min_length) {
    std::vector<std::pair<double, unsigned>> crossed;
    for (unsigned child = 0; child < 8; ++child) {
        const auto [enter, exit] = cell_interval(ray, child_cube(cell, child));
        if (exit - enter > min_length) crossed.push_back({enter, child});
    }
    std::sort(crossed.begin(), crossed.end());
    std::vector<unsigned> out;
    for (const auto& [enter, child] : crossed) out.push_back(child);
    return out;
}

/// Compares the walk with the direct computation at `cell`, then descends into a random child
/// the walk visits; returns the number of levels compared.
int check_walk(const Ray& ray, const OctreeWalkRay& walk, NodeSlabs slabs, OctreeCube cell, std::mt19937& rng) {
    double smallest_direction = kInfinity, coordinate_ulps = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        if (ray.dir[axis] != 0.0f) smallest_direction = std::min(smallest_direction, double(std::abs(ray.dir[axis])));
        coordinate_ulps =
            std::max({coordinate_ulps, 1e-6 * std::abs(ray.origin[axis]), 1e-6 * std::abs(cell.lo[axis])});
    }
    int levels = 0;
    for (int depth = 0; depth < 6; ++depth, ++levels) {
        // Children crossed for less than this (ties at edges and corners) may or may not be
        // listed; everything longer must be, in order.
        const double min_length = 1e-4 * double(cell.size) / double(length(ray.dir));
        const std::vector<WalkedChild> walked = walk_children(walk, slabs, cell);
        std::vector<unsigned> walked_long;
        for (const WalkedChild& w : walked) {
            const auto [enter, exit] = cell_interval(ray, child_cube(cell, w.child));
            if (exit - enter > min_length) {
                walked_long.push_back(w.child);
                // The walk's parametric interval is the cell's, up to rounding: relative to t,
                // plus a few ulps of the coordinates divided by the direction across the plane.
                const double tolerance = 1e-4 * (std::abs(enter) + std::abs(exit) + double(cell.size)) +
                                         coordinate_ulps / smallest_direction;
                if (std::isfinite(enter)) CHECK(std::abs(double(w.slabs.t_enter()) - enter) <= tolerance);
                if (std::isfinite(exit)) CHECK(std::abs(double(w.slabs.t_exit()) - exit) <= tolerance);
            }
        }
        const std::vector<unsigned> expected = crossed_children(ray, cell, min_length);
        REQUIRE(walked_long == expected);
        if (expected.empty()) break;
        const unsigned next = expected[std::uniform_int_distribution<std::size_t>(0, expected.size() - 1)(rng)];
        const auto it =
            std::find_if(walked.begin(), walked.end(), [&](const WalkedChild& w) { return w.child == next; });
        slabs = it->slabs;
        cell = child_cube(cell, next);
    }
    return levels;
}

Ray random_ray_near(const OctreeCube& cube, std::mt19937& rng, bool inside, int zero_axes) {
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), sym(-1.0f, 1.0f);
    const Vec3f target = cube.lo + Vec3f{unit(rng), unit(rng), unit(rng)} * cube.size;
    Vec3f dir{sym(rng), sym(rng), sym(rng)};
    for (int k = 0; k < zero_axes; ++k) dir[int(rng() % 3)] = (rng() & 1) ? 0.0f : -0.0f;
    if (dir.x == 0.0f && dir.y == 0.0f && dir.z == 0.0f) dir.x = 1.0f;
    Ray ray;
    ray.dir = dir;
    ray.origin = inside ? target : target - dir * (3.0f * cube.size / length(dir));
    return ray;
}

}  // namespace

TEST_CASE("the walk visits exactly the children a line crosses, ordered by entry, at every level") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> coordinate(-50.0f, 50.0f), size(0.5f, 20.0f);
    int levels = 0;
    for (int i = 0; i < 3000; ++i) {
        const OctreeCube cube{{coordinate(rng), coordinate(rng), coordinate(rng)}, size(rng)};
        CAPTURE(i);
        const Ray ray = random_ray_near(cube, rng, i % 3 == 0, i % 4 == 0 ? 1 + i % 2 : 0);
        OctreeWalkRay walk;
        NodeSlabs slabs;
        const bool entered = enter_root(ray, cube, walk, slabs);
        const auto [enter, exit] = cell_interval(ray, cube);
        if (!entered || slabs.t_enter() > slabs.t_exit()) {
            CHECK(exit - enter <= 1e-4 * double(cube.size));  // only a line grazing the cube may be missed
            continue;
        }
        levels += check_walk(ray, walk, slabs, cube, rng);
    }
    CHECK(levels > 5000);  // the descent really went below the root
}

TEST_CASE("child numbering: bit 0 is x, bit 1 is y, bit 2 is z, and the walk follows the ray's sign") {
    const OctreeCube cube{{0, 0, 0}, 2.0f};
    auto children = [&](const Ray& ray) {
        OctreeWalkRay walk;
        NodeSlabs slabs;
        REQUIRE(enter_root(ray, cube, walk, slabs));
        std::vector<unsigned> out;
        for (const WalkedChild& w : walk_children(walk, slabs, cube)) out.push_back(w.child);
        return out;
    };
    CHECK(children({{-1, 0.5f, 0.5f}, {1, 0, 0}}) == std::vector<unsigned>{0, 1});
    CHECK(children({{3, 0.5f, 0.5f}, {-1, -0.0f, 0}}) == std::vector<unsigned>{1, 0});
    CHECK(children({{1.5f, -1, 1.5f}, {0, 1, 0}}) == std::vector<unsigned>{5, 7});
    CHECK(children({{0.5f, 1.5f, 3}, {0, 0, -1}}) == std::vector<unsigned>{6, 2});
    // Across the diagonal from corner to corner: the walk may pass through edge-touching children
    // with empty intervals, but starts in 0 and ends in 7.
    const std::vector<unsigned> diagonal = children({{-1, -1, -1}, {1, 1, 1}});
    CHECK(diagonal.front() == 0u);
    CHECK(diagonal.back() == 7u);
}

TEST_CASE("a ray parallel to axes gets infinite slab parameters and midpoints, never NaN") {
    const OctreeCube cube{{-1, -1, -1}, 2.0f};
    for (const float zero : {0.0f, -0.0f}) {
        for (const float side : {-0.25f, 0.25f}) {
            const Ray ray{{side, -5, side}, {zero, 1, zero}};
            OctreeWalkRay walk;
            NodeSlabs slabs;
            REQUIRE(enter_root(ray, cube, walk, slabs));
            CHECK(walk.parallel == 5u);
            CHECK(walk.mirror == 0u);
            CHECK(slabs.t0.x == -kInfinity);
            CHECK(slabs.t1.z == kInfinity);
            const Vec3f tm = slab_midpoints(walk, slabs, cube);
            CHECK(tm.x == (side < 0 ? kInfinity : -kInfinity));
            const std::vector<WalkedChild> walked = walk_children(walk, slabs, cube);
            const unsigned xz = side < 0 ? 0u : 5u;  // the lower or the upper x and z half
            REQUIRE(walked.size() == 2);
            CHECK(walked[0].child == xz);
            CHECK(walked[1].child == (xz | 2u));
            for (const WalkedChild& w : walked) {
                CHECK(!std::isnan(w.slabs.t_enter()));
                CHECK(!std::isnan(w.slabs.t_exit()));
            }
        }
    }
}

TEST_CASE("a line outside the slab it runs parallel to, or a zero direction, misses the cube") {
    const OctreeCube cube{{0, 0, 0}, 1.0f};
    OctreeWalkRay walk;
    NodeSlabs slabs;
    CHECK_FALSE(enter_root({{2, 0.5f, -1}, {0, 0, 1}}, cube, walk, slabs));
    CHECK_FALSE(enter_root({{0.5f, 0.5f, 0.5f}, {0, -0.0f, 0}}, cube, walk, slabs));
    CHECK(enter_root({{1, 0.5f, -1}, {0, 0, 1}}, cube, walk, slabs));  // on the face: inside
}
