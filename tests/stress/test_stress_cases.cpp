// Every stress case with few rays, on every structure, runnable width and query: no leak, no
// disagreement with the double-precision reference beyond hit_judge.h's tolerances.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "core/reference.h"
#include "stress/stress_cases.h"
#include "stress/stress_runner.h"
#include "support/sanitizer_workload.h"

namespace trident {
namespace {

// Fewer rays under the sanitizers (support/sanitizer_workload.h): every case, structure, width and
// query still runs, on 150 rays (ten 16-lane packets) and the brute force's sanity row on 30.
constexpr std::size_t kRaysPerCase = testing::workload(1500, 10);

TEST_CASE("every stress case passes on every structure, width and query") {
    StressRunOptions options;
    options.brute_rays = testing::workload(300, 10);
    for (const StressCaseInfo& info : stress_cases()) {
        const StressCase stress_case = make_stress_case(info.name, kRaysPerCase, 42);
        REQUIRE(stress_case.rays.size() == kRaysPerCase);
        REQUIRE(stress_case.must_hit.size() == kRaysPerCase);
        std::size_t configurations = 0;
        run_stress_case(stress_case, options, [&](const StressTally& t) {
            ++configurations;
            INFO(t.case_name, " ", to_string(t.accel), " ", to_string(t.width), " ", to_string(t.query));
            CHECK(t.rays == (t.accel == AccelKind::brute ? options.brute_rays : kRaysPerCase));
            CHECK(t.reference_rays > 0);
            CHECK(t.leaks == 0);
            CHECK(t.hit_miss_disagreements == 0);
            CHECK(t.triangle_disagreements == 0);
            CHECK(t.t_beyond_tolerance == 0);
            CHECK(t.non_finite == 0);
        });
        CHECK(configurations == 2 * built_accel_kinds().size() * runnable_widths().size());
    }
}

TEST_CASE("a stress case is the same for the same seed and differs for another") {
    const StressCase a = make_stress_case("sphere", 50, 7), b = make_stress_case("sphere", 50, 7),
                     c = make_stress_case("sphere", 50, 8);
    REQUIRE(a.rays.size() == 50);
    bool same = true, differs = false;
    for (std::size_t i = 0; i < 50; ++i) {
        same = same && a.rays[i].origin == b.rays[i].origin && a.rays[i].dir == b.rays[i].dir;
        differs = differs || !(a.rays[i].dir == c.rays[i].dir);
    }
    CHECK(same);
    CHECK(differs);
}

TEST_CASE("closed-mesh cases mark every ray must-hit and the reference hits each") {
    for (const char* name : {"sphere", "cube", "teapot", "axis_parallel", "split_planes", "octree_centres"}) {
        const StressCase c = make_stress_case(name, 200, 3);
        INFO(name);
        const std::vector<Triangle> triangles = gather_triangles(c.mesh);
        for (std::size_t i = 0; i < c.rays.size(); ++i) {
            CHECK(c.must_hit[i] == 1);
            CHECK(trace_reference(triangles, c.rays[i]).is_hit());
        }
    }
}

TEST_CASE("the suite catches a test that is not watertight: Möller–Trumbore leaks on the cube") {
    StressRunOptions options;
    options.accels = {AccelKind::bvh};
    options.widths = {SimdWidth::scalar};
    options.test = TriangleTest::moller_trumbore;
    const StressCase cube = make_stress_case("cube", 3000, 42);
    run_stress_case(cube, options, [&](const StressTally& t) {
        INFO(to_string(t.query));
        CHECK(t.leaks > 0);
    });
}

TEST_CASE("the suite catches a slab test that is not robust: the fast one leaks on axis-parallel rays") {
    // Rays along the cube's tessellation planes with +0/-0 components: the fast slab test turns an
    // origin on a box face into 0 * inf = NaN and drops the box. Every width must show it. The
    // binary BVH's fast test is that plain formula; the wide BVH's orders the planes per ray, which
    // leaves such a NaN to min and max and so does not leak here (wide_box_test.h).
    const StressCase axis_parallel = make_stress_case("axis_parallel", 4000, 7);
    for (SlabTest slabs : {SlabTest::robust, SlabTest::fast}) {
        StressRunOptions options;
        options.accels = {AccelKind::bvh2};
        options.slabs = slabs;
        run_stress_case(axis_parallel, options, [&](const StressTally& t) {
            INFO(to_string(slabs), " ", to_string(t.width), " ", to_string(t.query));
            if (slabs == SlabTest::robust)
                CHECK(t.failures() == 0);
            else
                CHECK(t.leaks > 0);
        });
    }
}

TEST_CASE("unknown case names are refused") { CHECK_THROWS_AS(make_stress_case("no_such_case", 10, 1), std::invalid_argument); }

}  // namespace
}  // namespace trident
