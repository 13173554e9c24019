// BvhBuilder::automatic: which meshes get the tree with spatial splits, and that the trees say
// what built them.
#include <doctest/doctest.h>
#include <tbb/task_arena.h>

#include "accel/bvh/builder_choice.h"
#include "accel/bvh/bvh.h"
#include "accel/bvh/wide_bvh.h"
#include "support/random_scenes.h"

using namespace trident;
using namespace trident::testing;

namespace {

/// `mesh` with `other`'s triangles added.
Mesh joined(Mesh mesh, const Mesh& other) {
    for (std::size_t i = 0; i < other.triangle_count(); ++i) {
        const Triangle t = triangle_of(other, i);
        mesh.add_triangle(mesh.add_vertex(t.a), mesh.add_vertex(t.b), mesh.add_vertex(t.c));
    }
    return mesh;
}

}  // namespace

TEST_CASE("spatial splits are tried where large triangles hold the area, not where every triangle is tiny") {
    // 20,000 triangles of at most 0.004 a side in [-1, 1]^3: each box under 1e-6 of the scene's
    // area, as a scanned mesh's are.
    const Mesh fine = random_soup(20000, 41, 0.002f);
    CHECK(bvh::large_triangle_share(fine) == 0.0);
    CHECK_FALSE(bvh::tries_spatial_splits(fine));
    // The same with 30 triangles across the whole box (walls among small detail).
    const Mesh walls = joined(fine, soup_with_large_triangles(0, 30, 42));
    const double share = bvh::large_triangle_share(walls);
    CHECK(share > 0.9);  // 30 boxes of the scene's size against 20,000 of a millionth of it
    CHECK(share <= 1.0);
    CHECK(bvh::tries_spatial_splits(walls));
    // Nothing to weigh: no triangles, or a scene box of no area.
    CHECK_FALSE(bvh::tries_spatial_splits(Mesh{}));
    Mesh point;
    const auto p = point.add_vertex({1.0f, 2.0f, 3.0f});
    point.add_triangle(p, p, p);
    CHECK(bvh::large_triangle_share(point) == 0.0);
}

TEST_CASE("the tree with spatial splits is kept only where its SAH is at least 1% lower") {
    CHECK(bvh::spatial_tree_pays(15.49, 16.67));
    CHECK_FALSE(bvh::spatial_tree_pays(6.08, 6.10));  // within 1%
    CHECK_FALSE(bvh::spatial_tree_pays(8.36, 8.04));  // higher
    CHECK_FALSE(bvh::spatial_tree_pays(9.9, 10.0));
}

TEST_CASE("the share does not depend on the number of threads") {
    const Mesh mesh = soup_with_large_triangles(100000, 20, 43);
    double one_thread = -1.0;
    tbb::task_arena(1).execute([&] { one_thread = bvh::large_triangle_share(mesh); });
    CHECK(bvh::large_triangle_share(mesh) == one_thread);
}

TEST_CASE("auto builds the tree named by its options and statistics: per mesh for the wide BVH, binned for the binary") {
    const Mesh fine = random_soup(5000, 44, 0.002f);
    const Mesh walls = soup_with_large_triangles(3000, 30, 45);
    const auto wide_fine = WideBvh<8, 4>::build(fine, BvhOptions{});
    CHECK(wide_fine.options().builder == BvhBuilder::binned_sah);
    CHECK(wide_fine.stats().builder == "binned_sah");
    // Large triangles across small ones: spatial splits lower the SAH by far more than 1%, so the
    // tree with them is kept, and it is the one --bvh-builder spatial builds.
    BvhOptions spatial;
    spatial.builder = BvhBuilder::spatial_sah;
    BvhOptions binned;
    binned.builder = BvhBuilder::binned_sah;
    const auto wide_walls = WideBvh<8, 4>::build(walls, BvhOptions{});
    const auto wide_spatial = WideBvh<8, 4>::build(walls, spatial), wide_binned = WideBvh<8, 4>::build(walls, binned);
    REQUIRE(bvh::spatial_tree_pays(wide_spatial.stats().sah_cost, wide_binned.stats().sah_cost));
    CHECK(wide_walls.options().builder == BvhBuilder::spatial_sah);
    CHECK(wide_walls.stats().builder == "spatial_sah");
    CHECK(wide_walls.stats().sah_cost == wide_spatial.stats().sah_cost);
    CHECK(wide_walls.stats().references == wide_spatial.stats().references);
    // A plane of 800 large triangles side by side: spatial splits are tried, but object splits
    // already leave no overlap, so the binned tree is kept.
    Mesh grid;
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 20; ++x) {
            const auto corner = [&](int dx, int dy) { return grid.add_vertex({float(x + dx), float(y + dy), 0.0f}); };
            const auto a = corner(0, 0), b = corner(1, 0), c = corner(1, 1), d = corner(0, 1);
            grid.add_triangle(a, b, c);
            grid.add_triangle(a, c, d);
        }
    REQUIRE(bvh::tries_spatial_splits(grid));
    const auto wide_grid = WideBvh<8, 4>::build(grid, BvhOptions{});
    CHECK(wide_grid.options().builder == BvhBuilder::binned_sah);
    CHECK(wide_grid.stats().references == grid.triangle_count());
    const Bvh binary = Bvh::build(walls);
    CHECK(binary.options().builder == BvhBuilder::binned_sah);
    CHECK(binary.stats().builder == "binned_sah");
    CHECK(binary.stats().references == walls.triangle_count());
}
