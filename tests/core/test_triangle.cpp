#include <doctest/doctest.h>

#include "core/intersect_triangle.h"
#include "core/reference.h"

using namespace trident;

namespace {
const Triangle kUnit{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

template <TriangleTest Test>
bool hits(const Ray& ray, const Triangle& tri, TriangleHit& h) {
    return TriangleIntersector<Test>(ray).intersect(tri, ray.tmax, h);
}
}  // namespace

TEST_CASE("both triangle tests hit the interior with the right t and barycentrics") {
    const Ray ray{{0.25f, 0.5f, 2.0f}, {0, 0, -1}};
    for (auto test : {TriangleTest::watertight, TriangleTest::moller_trumbore}) {
        CAPTURE(to_string(test));
        TriangleHit h{};
        const bool hit = test == TriangleTest::watertight ? hits<TriangleTest::watertight>(ray, kUnit, h)
                                                          : hits<TriangleTest::moller_trumbore>(ray, kUnit, h);
        REQUIRE(hit);
        CHECK(h.t == doctest::Approx(2.0f));
        CHECK(h.u == doctest::Approx(0.25f));
        CHECK(h.v == doctest::Approx(0.5f));
    }
    CHECK(intersect_reference(ray, kUnit) == doctest::Approx(2.0));
}
