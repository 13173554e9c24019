// Tracing through the octree against the double-precision brute force: random soups, awkward
// rays (node centres, centre planes, cell edges, axis-parallel with +0 and -0), any hit, ray
// windows, and the built-in scenes when they exist.
#include <doctest/doctest.h>

#include <random>
#include <string>
#include <vector>

#include "accel/brute/brute_force.h"
#include "accel/octree/octree.h"
#include "octree/octree_meshes.h"
#include "octree/octree_test_support.h"
#include "support/camera_rays.h"
#include "support/random_scenes.h"
#include "support/reference_check.h"
#include "support/sanitizer_workload.h"

#if __has_include("scenes/builtin.h")
#include "scenes/builtin.h"
#define TRIDENT_TEST_BUILTIN_SCENES 1
#endif

using namespace trident;
using namespace trident::testing;

namespace {

std::vector<Hit> trace(const Octree& tree, std::span<const Ray> rays) {
    std::vector<Hit> hits;
    hits.reserve(rays.size());
    for (const Ray& ray : rays) hits.push_back(tree.intersect(ray));
    return hits;
}

void check_agreement(const Mesh& mesh, const Octree& tree, std::span<const Ray> rays) {
    const std::vector<Triangle> triangles = gather_triangles(mesh);
    const std::vector<Hit> hits = trace(tree, rays);
    require_agreement(compare_with_reference<Hit>(triangles, rays, hits));
}

/// The same answers as the single-precision brute force with the same triangle test, for rays
/// where float and double may legitimately disagree (aimed at a vertex many triangles share).
void check_same_as_brute_force(const Mesh& mesh, const Octree& tree, std::span<const Ray> rays) {
    const BruteForce brute = BruteForce::build(mesh);
    std::size_t hit_miss = 0, distance = 0;
    for (const Ray& ray : rays) {
        const Hit a = tree.intersect(ray), b = brute.intersect(ray);
        hit_miss += a.is_hit() != b.is_hit();
        distance += a.is_hit() && b.is_hit() && !nearly_equal_t(a.t, b.t);
        CHECK(tree.occluded(ray) == b.is_hit());
    }
    CHECK(hit_miss == 0);
    CHECK(distance == 0);
}

/// Any hit agrees with the closest hit: a ray occluded iff it hits, and nothing before the closest
/// hit. Also checks the reference's any-hit answer.
void check_any_hit(const Mesh& mesh, const Octree& tree, std::span<const Ray> rays) {
    const std::vector<Triangle> triangles = gather_triangles(mesh);
    std::size_t disagreements = 0, early_hits = 0, reference_disagreements = 0;
    for (const Ray& ray : rays) {
        const Hit hit = tree.intersect(ray);
        disagreements += tree.occluded(ray) != hit.is_hit();
        reference_disagreements += tree.occluded(ray) != occluded_reference(triangles, ray);
        if (hit.is_hit()) {
            Ray before = ray;
            before.tmax = hit.t * (1.0f - 1e-3f);
            early_hits += tree.occluded(before);
        }
    }
    CHECK(disagreements == 0);
    CHECK(early_hits == 0);
    CHECK(reference_disagreements == 0);
}

}  // namespace

TEST_CASE("closest hits agree with the double brute force on random soups, whatever the options") {
    for (const std::uint32_t seed : {1u, 2u, 3u}) {
        const Mesh mesh = random_soup(400, seed, seed == 3 ? 0.5f : 0.15f);
        const std::vector<Ray> rays = random_rays(mesh.bounds(), 400, seed + 100);
        for (const int depth : {0, 1, 4, 8, 12}) {
            for (const OctreeOverlap overlap : {OctreeOverlap::triangle, OctreeOverlap::bounding_box}) {
                CAPTURE(seed);
                CAPTURE(depth);
                CAPTURE(int(overlap));
                check_agreement(mesh, Octree::build(mesh, {.max_depth = depth, .overlap = overlap}), rays);
            }
        }
    }
}

TEST_CASE("rays through node centres, in centre planes and along cell edges agree with the brute force") {
    for (const int depth : {3, 6}) {
        CAPTURE(depth);
        const Mesh mesh = random_soup(600, 31, 0.1f);
        const Octree tree = Octree::build(mesh, {.max_depth = depth});
        const std::vector<Ray> rays = rays_along_the_planes(tree, 5, 3);
        CHECK(rays.size() > 100);
        check_agreement(mesh, tree, rays);
        check_any_hit(mesh, tree, rays);
    }
    // Axis-aligned geometry on the planes themselves: the grid's lines fall on cell faces.
    const Mesh grid = flat_grid(16);
    const Octree tree = Octree::build(grid, {.max_depth = 6});
    check_agreement(grid, tree, rays_along_the_planes(tree, 8, 3));
}

TEST_CASE("rays from inside the scene with tmin/tmax windows agree with the brute force") {
    const Mesh mesh = random_soup(500, 41, 0.15f);
    const Octree tree = Octree::build(mesh, {});
    const std::vector<Ray> rays = windowed_rays_from_inside(mesh.bounds(), 600, 42);
    check_agreement(mesh, tree, rays);
    check_any_hit(mesh, tree, rays);
}

TEST_CASE("any hit agrees with closest hit and with the reference") {
    const Mesh mesh = random_soup(500, 51, 0.1f);
    const Octree tree = Octree::build(mesh, {});
    check_any_hit(mesh, tree, random_rays(mesh.bounds(), 600, 52));
}

TEST_CASE("flat, far-from-origin, guarded and degenerate scenes trace like the brute force") {
    SUBCASE("a plane, with rays in it and across it") {
        const Mesh mesh = flat_grid(40);
        const Octree tree = Octree::build(mesh, {});
        std::vector<Ray> rays = random_rays(mesh.bounds(), 400, 61);
        for (int i = 0; i < 50; ++i)  // in the plane itself: the watertight test reports no hit
            rays.push_back({{-0.5f, 0.013f * float(i), 0.5f}, normalize(Vec3f{1.0f, 0.3f, 0.0f})});
        check_agreement(mesh, tree, rays);
    }
    SUBCASE("a soup 10^4 away from the origin") {
        const Mesh mesh = translated(random_soup(400, 62, 0.1f), {1e4f, -2e4f, 5e3f});
        check_agreement(mesh, Octree::build(mesh, {}), random_rays(mesh.bounds(), 400, 63));
    }
    SUBCASE("a tree the reference guard stopped") {
        const Mesh mesh = fan_around(300, {0.1f, 0.2f, 0.3f}, 64);
        const Octree tree = Octree::build(mesh, {.max_depth = 12, .max_references = 15000});
        CHECK(!tree.warning().empty());
        check_agreement(mesh, tree, random_rays(mesh.bounds(), 300, 65));
    }
    SUBCASE("a fan around one point, rays aimed at the point") {
        const Mesh mesh = fan_around(200, {0.1f, 0.2f, 0.3f}, 66);
        const Octree tree = Octree::build(mesh, {.max_depth = 8});
        std::vector<Ray> rays = random_rays(mesh.bounds(), 200, 67);
        std::mt19937 rng(68);
        std::uniform_real_distribution<float> sym(-1.0f, 1.0f);
        check_agreement(mesh, tree, rays);
        for (int i = 0; i < 200; ++i) {
            const Vec3f d = normalize(Vec3f{sym(rng), sym(rng), sym(rng)});
            rays.push_back({Vec3f{0.1f, 0.2f, 0.3f} - d * 5.0f, d});
        }
        // Through the hub, edges graze the ray: the float test may see a hit the double one does
        // not, so compare with the float brute force.
        check_same_as_brute_force(mesh, tree, rays);
    }
}

TEST_CASE("the Möller-Trumbore traversal finds what the brute force finds with the same test") {
    const Mesh mesh = random_soup(400, 71, 0.15f);
    const Octree tree = Octree::build(mesh, {});
    const BruteForce brute = BruteForce::build(mesh);
    std::size_t hit_miss = 0, distance = 0;
    for (const Ray& ray : random_rays(mesh.bounds(), 500, 72)) {
        NoCounters none;
        const Hit a = tree.intersect<TriangleTest::moller_trumbore>(ray, none);
        const Hit b = brute.intersect<TriangleTest::moller_trumbore>(ray, none);
        hit_miss += a.is_hit() != b.is_hit();
        distance += a.is_hit() && b.is_hit() && !nearly_equal_t(a.t, b.t);
        CHECK(tree.occluded<TriangleTest::moller_trumbore>(ray, none) == b.is_hit());
    }
    CHECK(hit_miss == 0);
    CHECK(distance == 0);
}

TEST_CASE("the counters see the nodes visited and the triangles tested") {
    const Mesh mesh = random_soup(4000, 81, 0.05f);
    const Octree tree = Octree::build(mesh, {});
    TraversalCounters missed;
    tree.intersect<TriangleTest::watertight>({{10, 10, 10}, {1, 0, 0}}, missed);  // misses the cube
    CHECK(missed.nodes_visited == 0);
    CHECK(missed.triangles_tested == 0);
    TraversalCounters total;
    const std::vector<Ray> rays = random_rays(mesh.bounds(), 300, 82);
    for (const Ray& ray : rays) {
        TraversalCounters one;
        const Hit hit = tree.intersect<TriangleTest::watertight>(ray, one);
        if (hit.is_hit()) {
            CHECK(one.nodes_visited >= 2);
            CHECK(one.triangles_tested >= 1);
        }
        total += one;
    }
    // The point of the tree: a small fraction of the triangles is tested.
    CHECK(double(total.triangles_tested) / double(rays.size()) < 0.05 * double(mesh.triangle_count()));
}

TEST_CASE("the traversal does no work outside the ray's window and stops at the first hit") {
    Mesh mesh = flat_grid(32, 1.0f, 0.25f);
    mesh.append(flat_grid(32, 1.0f, 0.75f));
    const Octree tree = Octree::build(mesh, {});
    auto tested = [&](const Ray& ray) {
        TraversalCounters counters;
        tree.intersect<TriangleTest::watertight>(ray, counters);
        return counters.triangles_tested;
    };
    // Down through both planes: z = 0.75 at t = 1.25, z = 0.25 at t = 1.75.
    const Vec3f origin{0.31f, 0.47f, 2.0f}, down{0, 0, -1};
    CHECK(tested({origin, down}) <= tree.stats().max_leaf_size);  // the upper plane's leaf only
    CHECK(tested({origin, down, 0.0f, 1.1f}) == 0);               // cells after tmax are never entered
    // Cells before tmin (or behind the origin) are skipped: the lower plane's leaf only.
    CHECK(tested({origin, down, 1.4f}) <= tree.stats().max_leaf_size);
    CHECK(tested({origin + down * 1.4f, down}) <= tree.stats().max_leaf_size);
}

#ifdef TRIDENT_TEST_BUILTIN_SCENES
TEST_CASE("closest and any hits agree with the brute force on the built-in scenes") {
    for (const std::string& name : builtin_scene_names_under_test()) {
        CAPTURE(name);
        const Scene scene = make_builtin_scene(name);
        const Octree tree = Octree::build(scene.mesh, {});
        INFO(tree.stats().to_line());
        CHECK(tree.warning().empty());
        // The scene's own camera, plus random rays through its box; fewer on the largest scenes,
        // where each ray costs a million double-precision tests.
        const std::size_t count = scene.mesh.triangle_count() > 500000 ? 40 : 100;
        std::vector<Ray> rays = camera_rays(scene.camera, count, 91);
        const std::vector<Ray> random = random_rays(scene.mesh.bounds(), count, 92);
        rays.insert(rays.end(), random.begin(), random.end());
        check_agreement(scene.mesh, tree, rays);
        if (scene.mesh.triangle_count() < 300000) check_any_hit(scene.mesh, tree, std::span(rays).first(60));
    }
}
#endif
