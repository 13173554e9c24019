// The separating-axis triangle/box test against clipping, an independent way to decide overlap.
#include <doctest/doctest.h>

#include <random>

#include "core/triangle_box_overlap.h"
#include "support/triangle_box_clipping.h"

using namespace trident;
using testing::triangle_meets_box_by_clipping;

namespace {

bool sat(const Triangle& tri, const Vec3d& lo, const Vec3d& hi) {
    return triangle_overlaps_box(Vec3d(tri.a), Vec3d(tri.b), Vec3d(tri.c), (lo + hi) * 0.5, (hi - lo) * 0.5);
}

}  // namespace

TEST_CASE("the separating-axis test agrees with clipping on random triangles and boxes") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> coordinate(-2.0f, 2.0f);
    std::uniform_real_distribution<double> half(0.05, 1.0);
    int overlaps = 0, bbox_only = 0;
    for (int i = 0; i < 20000; ++i) {
        const Triangle tri{{coordinate(rng), coordinate(rng), coordinate(rng)},
                           {coordinate(rng), coordinate(rng), coordinate(rng)},
                           {coordinate(rng), coordinate(rng), coordinate(rng)}};
        const Vec3d centre{coordinate(rng) * 0.5, coordinate(rng) * 0.5, coordinate(rng) * 0.5};
        const Vec3d extent{half(rng), half(rng), half(rng)};
        // Clipping and the separating axes round differently, so compare with a margin: a clear
        // overlap for one is an overlap for the other, and a clear miss a miss.
        const Vec3d margin(1e-9);
        const bool clipped = triangle_meets_box_by_clipping(tri, centre - extent, centre + extent);
        CAPTURE(i);
        if (clipped) CHECK(sat(tri, centre - extent - margin, centre + extent + margin));
        if (sat(tri, centre - extent + margin, centre + extent - margin))
            CHECK(triangle_meets_box_by_clipping(tri, centre - extent, centre + extent));
        overlaps += clipped;
        const Aabb box = tri.bounds();
        const bool boxes_meet = box.lo.x <= centre.x + extent.x && box.hi.x >= centre.x - extent.x &&
                                box.lo.y <= centre.y + extent.y && box.hi.y >= centre.y - extent.y &&
                                box.lo.z <= centre.z + extent.z && box.hi.z >= centre.z - extent.z;
        bbox_only += boxes_meet && !clipped;
    }
    // Both outcomes are well represented, including triangles whose bounding box alone overlaps.
    CHECK(overlaps > 2000);
    CHECK(bbox_only > 1000);
}

TEST_CASE("triangle/box overlap: diagonal miss, touching faces, and degenerate triangles") {
    const Vec3d lo{0, 0, 0}, hi{1, 1, 1};
    // Its bounding box covers the unit box, the triangle passes beyond the corner (x + y = 2.5).
    CHECK_FALSE(sat({{2.5f, 0, -1}, {0, 2.5f, -1}, {1.25f, 1.25f, 2}}, lo, hi));
    CHECK(sat({{1, 0.5f, 0.5f}, {2, 0.5f, 0.5f}, {2, 0.7f, 0.5f}}, lo, hi));           // touches the x = 1 face
    CHECK(sat({{0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}}, lo, hi));  // a point inside
    CHECK_FALSE(sat({{1.5f, 0.5f, 0.5f}, {1.5f, 0.5f, 0.5f}, {1.5f, 0.5f, 0.5f}}, lo, hi));
    CHECK(sat({{-1, 0.5f, 0.5f}, {2, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}}, lo, hi));  // a segment through it
}
