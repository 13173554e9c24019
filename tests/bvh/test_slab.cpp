// The robust slab test of core/slab_test.h, one axis at a time (intersect_slabs) and three axes
// at once (the BVH's NodeBoxTest, one node or two side by side): axis-parallel rays (the 0 * inf
// trap), closed boxes, and no gap between boxes that share a face.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>

#include "accel/bvh/node_box_test.h"
#include "core/aabb.h"
#include "core/slab_test.h"

using namespace trident;

namespace {

const Aabb kUnitBox{{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}};

/// NodeBoxTest::enters_pair against enters() on each of the two nodes: the same decisions and,
/// where a node is entered, the same entry distance bit for bit.
void check_pair(const bvh::NodeBoxTest<>& test, const BvhNode& first, const BvhNode& second, const Ray& ray) {
    float t_first = -1.0f, t_second = -1.0f, alone_first = -1.0f, alone_second = -1.0f;
    const unsigned entered = test.enters_pair(first, second, ray.tmin, ray.tmax, t_first, t_second);
    const bool first_alone = test.enters(first, ray.tmin, ray.tmax, alone_first);
    const bool second_alone = test.enters(second, ray.tmin, ray.tmax, alone_second);
    CHECK(bool(entered & 1u) == first_alone);
    CHECK(bool(entered & 2u) == second_alone);
    CHECK(entered <= 3u);
    if (first_alone) CHECK(std::bit_cast<std::uint32_t>(t_first) == std::bit_cast<std::uint32_t>(alone_first));
    if (second_alone) CHECK(std::bit_cast<std::uint32_t>(t_second) == std::bit_cast<std::uint32_t>(alone_second));
}

/// Every form of the test, which must agree exactly; t_entry from the scalar one. The pair form
/// is checked with the box in either half beside the unit box.
bool hits(const Ray& ray, const Aabb& box, float& t_entry) {
    const bool scalar = intersect_slabs(SlabRay(ray.origin, ray.dir), box.lo, box.hi, ray.tmin, ray.tmax, t_entry);
    float node_entry = -1.0f;
    const bvh::NodeBoxTest<> test(ray);
    const BvhNode node = BvhNode::leaf(box, 0, 1), unit = BvhNode::leaf(kUnitBox, 0, 1);
    const bool node_hit = test.enters(node, ray.tmin, ray.tmax, node_entry);
    CHECK(node_hit == scalar);
    if (scalar) CHECK(node_entry == t_entry);
    check_pair(test, node, unit, ray);
    check_pair(test, unit, node, ray);
    return scalar;
}

}  // namespace

TEST_CASE("a ray running inside a face plane of the box (zero direction, origin on the plane) hits it, with no NaN") {
    for (int plane_axis = 0; plane_axis < 3; ++plane_axis)
        for (float plane : {0.0f, 1.0f})
            for (float zero : {0.0f, -0.0f}) {
                const int travel_axis = (plane_axis + 1) % 3, other_axis = (plane_axis + 2) % 3;
                Ray ray;
                ray.origin[plane_axis] = plane;
                ray.origin[travel_axis] = -1.0f;
                ray.origin[other_axis] = 0.5f;
                ray.dir[plane_axis] = zero;
                ray.dir[travel_axis] = 1.0f;
                ray.dir[other_axis] = zero;
                CAPTURE(plane_axis);
                CAPTURE(plane);
                CAPTURE(std::signbit(zero));
                for (float tmin : {0.0f, 0.5f, 1.5f}) {
                    ray.tmin = tmin;
                    float t_entry = -1.0f;
                    REQUIRE(hits(ray, kUnitBox, t_entry));
                    CHECK(!std::isnan(t_entry));
                    CHECK(t_entry == doctest::Approx(std::max(tmin, 1.0f)));
                }
                ray.tmin = 2.5f;  // starts beyond the box's far side
                float t_entry;
                CHECK_FALSE(hits(ray, kUnitBox, t_entry));
            }
}

TEST_CASE("a ray parallel to a slab just outside it misses, whatever the sign of its zero component") {
    for (float zero : {0.0f, -0.0f})
        for (float x : {std::nextafter(0.0f, -1.0f), std::nextafter(1.0f, 2.0f)}) {
            const Ray ray{{x, 0.5f, -1.0f}, {zero, zero, 1.0f}};
            float t_entry;
            CHECK_FALSE(hits(ray, kUnitBox, t_entry));
        }
}

TEST_CASE("a flat box is hit by a ray lying in its plane") {
    const Aabb flat{{0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 1.0f}};
    for (float zero : {0.0f, -0.0f}) {
        const Ray ray{{0.0f, 0.5f, -1.0f}, {zero, zero, 1.0f}, 0.25f};
        float t_entry;
        REQUIRE(hits(ray, flat, t_entry));
        CHECK(t_entry == doctest::Approx(1.0f));
    }
}

TEST_CASE("the box is closed and the ray interval too: touching at t_max or at a corner counts") {
    float t_entry;
    CHECK(hits(Ray{{-1.0f, 0.5f, 0.5f}, {1.0f, 0.0f, 0.0f}, 0.0f, 1.0f}, kUnitBox, t_entry));  // t_max at entry
    CHECK_FALSE(hits(Ray{{-1.0f, 0.5f, 0.5f}, {1.0f, 0.0f, 0.0f}, 0.0f, 0.999f}, kUnitBox, t_entry));
    CHECK(hits(Ray{{-1.0f, -1.0f, 0.5f}, {1.0f, 1.0f, 0.0f}}, kUnitBox, t_entry));  // through the edge (0, 0)
    CHECK(t_entry == doctest::Approx(1.0f));
    CHECK_FALSE(hits(Ray{{-1.0f, 0.5f, 0.5f}, {-1.0f, 0.0f, 0.0f}}, kUnitBox, t_entry));  // pointing away
}

namespace {

/// The slab test in double: exact enough to judge the float test, whose widening is ~1e-7.
bool hits_in_double(const Ray& ray, const Aabb& box) {
    double entry = ray.tmin, exit = ray.tmax;
    for (int axis = 0; axis < 3; ++axis) {
        const double inv = 1.0 / double(ray.dir[axis]);
        const double t0 = (double(box.lo[axis]) - double(ray.origin[axis])) * inv;
        const double t1 = (double(box.hi[axis]) - double(ray.origin[axis])) * inv;
        entry = std::max(entry, std::min(t0, t1));
        exit = std::min(exit, std::max(t0, t1));
    }
    return entry <= exit;
}

}  // namespace

TEST_CASE("every ray that touches a box in exact arithmetic hits it, even through the edges of a shared face") {
    // Two boxes sharing the face x = x1, far from the origin so that rounding is at its worst;
    // the rays aim at the edges of the shared face, where a test without Ize's widening drops
    // some of them from both boxes.
    const float x0 = 1000.1f, x1 = 1000.7f, x2 = 1001.3f;
    const Aabb boxes[2] = {{{x0, -3.3f, 7.1f}, {x1, -2.9f, 7.9f}}, {{x1, -3.3f, 7.1f}, {x2, -2.9f, 7.9f}}};
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), sym(-1.0f, 1.0f);
    int touching = 0, rejected = 0;
    for (int i = 0; i < 20000; ++i) {
        Vec3f p{x1, -3.3f + 0.4f * unit(rng), 7.1f + 0.8f * unit(rng)};
        if (i % 2)
            p.y = i % 4 == 1 ? -3.3f : -2.9f;
        else
            p.z = i % 4 == 0 ? 7.1f : 7.9f;
        const Vec3f origin = p + Vec3f{sym(rng), sym(rng), sym(rng)} * (5.0f + 50.0f * unit(rng));
        const Ray ray{origin, p - origin};
        for (const Aabb& box : boxes) {
            if (!hits_in_double(ray, box)) continue;
            ++touching;
            float t_entry;
            rejected += !hits(ray, box, t_entry);
        }
    }
    CHECK(touching > 10000);  // the rays do graze the boxes
    CHECK(rejected == 0);
}

TEST_CASE("the BVH's plane-ordered box test accepts exactly the boxes the robust slab test accepts") {
    // Origins and box planes on a coarse grid, so that origins often lie on a plane; directions
    // with +0 and -0 components, axis-parallel and oblique. hits() checks the NodeBoxTest (planes
    // ordered by the ray's signs, NaN ignored) against intersect_slabs (zero offsets replaced),
    // decision and entry distance.
    std::mt19937 rng(11);
    std::uniform_int_distribution<int> grid(-2, 2), pick(0, 4);
    const float components[5] = {0.0f, -0.0f, 1.0f, -1.0f, 0.375f};
    int accepted = 0, rays = 0;
    for (int i = 0; i < 20000; ++i) {
        Aabb box;
        for (int a = 0; a < 3; ++a) {
            const int lo = grid(rng), extent = grid(rng) + 2;  // 0 .. 4, flat boxes included
            box.lo[a] = float(lo);
            box.hi[a] = float(lo + extent);
        }
        Ray ray{{float(grid(rng)), float(grid(rng)), float(grid(rng))},
                {components[pick(rng)], components[pick(rng)], components[pick(rng)]}};
        if (ray.dir.x == 0.0f && ray.dir.y == 0.0f && ray.dir.z == 0.0f) continue;
        ray.tmin = i % 3 == 0 ? 0.5f : 0.0f;
        ++rays;
        float t_entry;
        accepted += hits(ray, box, t_entry);
    }
    CHECK(rays > 15000);
    CHECK(accepted > rays / 10);  // both outcomes are exercised
    CHECK(accepted < rays);
}
