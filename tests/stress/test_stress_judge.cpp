// The stress runner and its judge must be able to fail: known leaks, self-hits and wrong hits
// are counted, and the tolerances of hit_judge.h separate clear hits, clear misses and edges.
#include <doctest/doctest.h>

#include <cmath>

#include "stress/hit_judge.h"
#include "stress/stress_runner.h"

namespace trident {
namespace {

StressCase one_triangle_case() {
    StressCase c;
    c.name = "one_triangle";
    c.mesh.add_triangle(c.mesh.add_vertex({-1, -1, 0}), c.mesh.add_vertex({1, -1, 0}), c.mesh.add_vertex({0, 1, 0}));
    return c;
}

StressRunOptions bvh_scalar() {
    StressRunOptions options;
    options.accels = {AccelKind::bvh};
    options.widths = {SimdWidth::scalar};
    return options;
}

TEST_CASE("fit_triangle: inside, outside, on an edge, degenerate") {
    const Triangle tri{{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
    const Ray centre{{0, 0, 5}, {0, 0, -1}};
    const TriangleFit in = fit_triangle(centre, tri);
    CHECK(in.t == doctest::Approx(5.0));
    CHECK(in.must_hit(centre));
    const Ray outside{{3, 0, 5}, {0, 0, -1}};
    CHECK_FALSE(fit_triangle(outside, tri).may_hit(outside));
    const Ray edge{{0, -1, 5}, {0, 0, -1}};  // exactly on the edge a-b
    const TriangleFit on_edge = fit_triangle(edge, tri);
    CHECK(on_edge.may_hit(edge));
    CHECK_FALSE(on_edge.must_hit(edge));
    const Triangle flat{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
    CHECK(fit_triangle(centre, flat).degenerate());
    const Ray behind{{0, 0, -5}, {0, 0, -1}};
    CHECK_FALSE(fit_triangle(behind, tri).may_hit(behind));
}

TEST_CASE("fit_triangle: a ray in the triangle's plane may hit it along the shared segment, never must") {
    const Triangle tri{{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
    const Ray across{{-5, 0, 0}, {1, 0, 0}};  // in the plane z = 0, crossing x = -0.5 .. 0.5
    const TriangleFit in_plane = fit_triangle(across, tri);
    CHECK_FALSE(in_plane.degenerate());
    CHECK(in_plane.may_hit(across));
    CHECK_FALSE(in_plane.must_hit(across));
    CHECK(in_plane.t == doctest::Approx(4.5).epsilon(1e-3));  // widened by the rounding slack
    CHECK(in_plane.t + in_plane.t_tolerance == doctest::Approx(5.5).epsilon(1e-4));  // reaches the exit
    const Ray through_vertex{{0, 3, 0}, {0, -1, 0}};  // along the axis of symmetry, entering at c
    CHECK(fit_triangle(through_vertex, tri).t == doctest::Approx(2.0).epsilon(1e-3));
    const Ray beside{{-5, 2, 0}, {1, 0, 0}};  // in the plane, above the triangle
    CHECK_FALSE(fit_triangle(beside, tri).may_hit(beside));
    const Ray above{{-5, 0, 0.5}, {1, 0, 0}};  // parallel, off the plane
    CHECK_FALSE(fit_triangle(above, tri).may_hit(above));
    const Ray away{{-5, 0, 0}, {-1, 0, 0}};  // in the plane, pointing away
    CHECK_FALSE(fit_triangle(away, tri).may_hit(away));
}

TEST_CASE("a must-hit ray that misses is a leak, in both queries") {
    StressCase c = one_triangle_case();
    c.add_ray({{5, 5, 5}, {0, 0, -1}}, true);  // misses the triangle
    c.add_ray({{0, 0, 5}, {0, 0, -1}}, true);  // hits it
    std::size_t tallies = 0;
    run_stress_case(c, bvh_scalar(), [&](const StressTally& t) {
        ++tallies;
        CHECK(t.leaks == 1);
        CHECK(t.failures() == 1);
    });
    CHECK(tallies == 2);
}

TEST_CASE("hitting the start triangle is a triangle disagreement") {
    StressCase c = one_triangle_case();
    c.add_ray({{0, 0, 5}, {0, 0, -1}}, false, 0);
    run_stress_case(c, bvh_scalar(), [&](const StressTally& t) {
        if (t.query == StressQuery::closest_hit) CHECK(t.triangle_disagreements == 1);
    });
}

TEST_CASE("Möller–Trumbore is judged by the same rules: agreement on clear hits and misses") {
    StressCase c = one_triangle_case();
    c.add_ray({{0, 0, 5}, {0, 0, -1}}, false);
    c.add_ray({{4, 0, 5}, {0, 0, -1}}, false);
    StressRunOptions options = bvh_scalar();
    options.test = TriangleTest::moller_trumbore;
    run_stress_case(c, options, [&](const StressTally& t) {
        CHECK(t.reference_rays == 2);
        CHECK(t.failures() == 0);
        if (t.query == StressQuery::closest_hit) CHECK(t.max_relative_t_error < 1e-6);
    });
}

}  // namespace
}  // namespace trident
