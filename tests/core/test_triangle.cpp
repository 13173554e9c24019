#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "accel/brute/brute_force.h"
#include "core/intersect_triangle.h"
#include "core/ray_offset.h"
#include "core/reference.h"

using namespace trident;

namespace {

const Triangle kUnit{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

template <TriangleTest Test>
bool hits(const Ray& ray, const Triangle& tri, TriangleHit& h) {
    return TriangleIntersector<Test>(ray).intersect(tri, ray.tmax, h);
}

bool hits(TriangleTest test, const Ray& ray, const Triangle& tri) {
    TriangleHit h{};
    return test == TriangleTest::watertight ? hits<TriangleTest::watertight>(ray, tri, h)
                                            : hits<TriangleTest::moller_trumbore>(ray, tri, h);
}

constexpr TriangleTest kBothTests[] = {TriangleTest::watertight, TriangleTest::moller_trumbore};

}  // namespace

TEST_CASE("both triangle tests hit the interior with the right t and barycentrics") {
    const Ray ray{{0.25f, 0.5f, 2.0f}, {0, 0, -1}};
    TriangleHit w{}, m{};
    REQUIRE(hits<TriangleTest::watertight>(ray, kUnit, w));
    REQUIRE(hits<TriangleTest::moller_trumbore>(ray, kUnit, m));
    for (const TriangleHit& h : {w, m}) {
        CHECK(h.t == doctest::Approx(2.0f));
        CHECK(h.u == doctest::Approx(0.25f));
        CHECK(h.v == doctest::Approx(0.5f));
    }
    CHECK(intersect_reference(ray, kUnit) == doctest::Approx(2.0));
}

TEST_CASE("misses, back faces, parallel rays and the t interval") {
    for (TriangleTest test : kBothTests) {
        CAPTURE(to_string(test));
        CHECK_FALSE(hits(test, Ray{{0.8f, 0.8f, 1.0f}, {0, 0, -1}}, kUnit));          // beyond the hypotenuse
        CHECK(hits(test, Ray{{0.2f, 0.2f, -1.0f}, {0, 0, 1}}, kUnit));                // back face: no culling
        CHECK_FALSE(hits(test, Ray{{0.2f, 0.2f, 1.0f}, {1, 0, 0}}, kUnit));           // parallel, off the plane
        CHECK_FALSE(hits(test, Ray{{-1.0f, 0.2f, 0.0f}, {1, 0, 0}}, kUnit));          // in the plane
        CHECK_FALSE(hits(test, Ray{{0.2f, 0.2f, 1.0f}, {0, 0, 1}}, kUnit));           // behind the origin
        CHECK_FALSE(hits(test, Ray{{0.2f, 0.2f, 1.0f}, {0, 0, -1}, 0.0f, 1.0f}, kUnit));  // tmax exclusive
        CHECK(hits(test, Ray{{0.2f, 0.2f, 1.0f}, {0, 0, -1}, 1.0f, 2.0f}, kUnit));        // tmin inclusive
        CHECK_FALSE(hits(test, Ray{{0.2f, 0.2f, 1.0f}, {0, 0, -1}}, Triangle{{0, 0, 0}, {1, 1, 0}, {2, 2, 0}}));  // degenerate
    }
}

TEST_CASE("edges and vertices count as hits for both tests") {
    for (TriangleTest test : kBothTests) {
        CAPTURE(to_string(test));
        CHECK(hits(test, Ray{{0.5f, 0.0f, 1.0f}, {0, 0, -1}}, kUnit));   // on edge a-b
        CHECK(hits(test, Ray{{0.0f, 0.5f, 1.0f}, {0, 0, -1}}, kUnit));   // on edge a-c
        CHECK(hits(test, Ray{{0.5f, 0.5f, 1.0f}, {0, 0, -1}}, kUnit));   // on the hypotenuse
        CHECK(hits(test, Ray{{0.0f, 0.0f, 1.0f}, {0, 0, -1}}, kUnit));   // on vertex a
        CHECK(hits(test, Ray{{1.0f, 0.0f, 1.0f}, {0, 0, -1}}, kUnit));   // on vertex b
    }
}

TEST_CASE("watertight: a ray through the shared edge of two triangles hits at least one, from any direction") {
    // A square split along its diagonal; rays aimed at random points of the diagonal.
    const Triangle lower{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, upper{{0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), sym(-1.0f, 1.0f);
    std::size_t leaks = 0;
    for (int i = 0; i < 20000; ++i) {
        const float s = unit(rng);
        const Vec3f target{s, s, 0.0f};
        const Vec3f origin{sym(rng) * 3.0f, sym(rng) * 3.0f, 0.5f + unit(rng) * 3.0f};
        const Ray ray{origin, target - origin};
        leaks += !hits(TriangleTest::watertight, ray, lower) && !hits(TriangleTest::watertight, ray, upper);
    }
    CHECK(leaks == 0);
}

TEST_CASE("the double-precision reference finds the nearest of stacked triangles and breaks ties by index") {
    std::vector<Triangle> stack;
    for (float z : {1.0f, 3.0f, 2.0f, 3.0f}) stack.push_back({{-1, -1, z}, {1, -1, z}, {0, 1, z}});
    const Ray down{{0, 0, 10}, {0, 0, -1}};
    const ReferenceHit hit = trace_reference(stack, down);
    CHECK(hit.triangle == 1);  // z = 3 is nearest and appears twice: the lower index wins
    CHECK(hit.t == doctest::Approx(7.0));
    CHECK(occluded_reference(stack, down));
    CHECK_FALSE(occluded_reference(stack, Ray{{0, 0, 10}, {0, 0, -1}, 0.0f, 6.0f}));
    CHECK_FALSE(trace_reference(stack, Ray{{5, 5, 10}, {0, 0, -1}}).is_hit());
}

TEST_CASE("the float brute-force structure agrees with the reference on a closed cube seen from inside") {
    Mesh cube;
    for (int i = 0; i < 8; ++i) cube.add_vertex({float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
    const std::uint32_t faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (const auto& f : faces) {
        cube.add_triangle(f[0], f[1], f[2]);
        cube.add_triangle(f[0], f[2], f[3]);
    }
    const BruteForce brute = BruteForce::build(cube);
    const std::vector<Triangle> triangles = gather_triangles(cube);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> inside(0.05f, 0.95f), sym(-1.0f, 1.0f);
    for (int i = 0; i < 2000; ++i) {
        const Ray ray{{inside(rng), inside(rng), inside(rng)}, normalize(Vec3f{sym(rng), sym(rng), sym(rng)})};
        const Hit hit = brute.intersect(ray);
        const ReferenceHit ref = trace_reference(triangles, ray);
        REQUIRE(hit.is_hit());  // closed: every ray from inside leaves through a face
        REQUIRE(ref.is_hit());
        CHECK(double(hit.t) == doctest::Approx(ref.t).epsilon(1e-5));
        CHECK(brute.occluded(ray));
    }
}

TEST_CASE("watertight: a ray leaving a large plane from an offset origin does not hit its coplanar triangles") {
    // Two triangles 3,200 units wide in the plane y = -1.572159 (Room's floor, ../shared/scenes):
    // an origin offset off that plane (core/ray_offset.h) lies 256 ulps of its y above it, far
    // less than the rounding of t on corners 1,000 units away, so the float t of the crossing
    // behind the origin can round to >= 0. Rays leaving upward must not hit the floor. (The
    // other way, a ray from such an origin back down into the floor can miss it, its t rounding
    // below 0; the renderer makes no such rays: shadow and hemisphere rays leave the surface.)
    const float y = -1.5721590f;
    const Triangle floor[2] = {{{-1600, y, -1600}, {1600, y, 1600}, {1600, y, -1600}},
                               {{-1600, y, -1600}, {-1600, y, 1600}, {1600, y, 1600}}};
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> coordinate(-1500.0f, 1500.0f), lean(-1.0f, 1.0f), rise(0.05f, 1.0f);
    int leaving_hits = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3f origin = offset_ray_origin({coordinate(rng), y, coordinate(rng)}, {0, 1, 0});
        const Vec3f up = normalize(Vec3f{lean(rng), rise(rng), lean(rng)});
        for (const Triangle& tri : floor) leaving_hits += hits(TriangleTest::watertight, Ray{origin, up}, tri);
    }
    CHECK(leaving_hits == 0);
}

TEST_CASE("watertight: a sliver far from the origin stays hit where its t is within rounding of 0") {
    // 10 units long and 1e-5 wide, 22 units away: its determinant is so small that the bound on
    // t's rounding exceeds t itself. The hit must be decided again, not dropped, or rays leak
    // through the gap the sliver fills.
    const Triangle sliver{{0, 0, 0}, {10, 0, 0}, {5, 1e-5f, 0}};
    TriangleHit h{};
    REQUIRE(hits<TriangleTest::watertight>(Ray{{5.0f, 4e-6f, 22.0f}, {0, 0, -1}}, sliver, h));
    CHECK(h.t == doctest::Approx(22.0f));
}
