// Tracing through the kd-tree against the double-precision brute force: random soups, rays lying
// in split planes or starting on them, axis-parallel rays with +0 and -0, ray windows, any hit,
// counters, and the built-in scenes.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <span>
#include <vector>

#include "accel/kdtree/kdtree.h"
#include "kdtree/kd_test_support.h"
#include "scenes/builtin.h"
#include "support/camera_rays.h"
#include "support/random_scenes.h"
#include "support/reference_check.h"
#include "support/sanitizer_workload.h"

using namespace trident;
using namespace trident::testing;

namespace {

template <TriangleTest Test = TriangleTest::watertight>
std::vector<Hit> trace(const KdTree& tree, std::span<const Ray> rays) {
    std::vector<Hit> hits;
    hits.reserve(rays.size());
    NoCounters counters;
    for (const Ray& ray : rays) hits.push_back(tree.intersect<Test>(ray, counters));
    return hits;
}

template <TriangleTest Test = TriangleTest::watertight>
void check_agreement(const KdTree& tree, const Mesh& mesh, std::span<const Ray> rays) {
    const std::vector<Triangle> triangles = gather_triangles(mesh);
    const std::vector<Hit> hits = trace<Test>(tree, rays);
    require_agreement(compare_with_reference<Hit>(triangles, rays, hits));
}

/// Any hit agrees with the closest hit on hit or miss, and with the reference.
void check_any_hit(const KdTree& tree, const Mesh& mesh, std::span<const Ray> rays) {
    const std::vector<Triangle> triangles = gather_triangles(mesh);
    std::size_t disagreements = 0;
    for (const Ray& ray : rays) {
        const bool occluded = tree.occluded(ray);
        disagreements += occluded != tree.intersect(ray).is_hit();
        disagreements += occluded != occluded_reference(triangles, ray);
    }
    CHECK(disagreements == 0);
}

/// Rays in the planes the tree split at: origin on the plane, direction +0 or -0 across it
/// (lying in the plane), and rays starting on the plane and crossing it. Origins avoid the
/// triangles themselves, where float and double disagree about a hit at t = 0.
std::vector<Ray> split_plane_rays(const KdTree& tree, std::size_t max_planes, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), sym(-1.0f, 1.0f);
    std::vector<SplitPlane> planes = kd_split_planes(tree);
    std::shuffle(planes.begin(), planes.end(), rng);
    planes.resize(std::min(planes.size(), max_planes));
    const Aabb box = tree.bounds();
    std::vector<Ray> rays;
    for (const SplitPlane& plane : planes) {
        const int a = plane.axis, b = (a + 1) % 3, c = (a + 2) % 3;
        for (int k = 0; k < 6; ++k) {
            Ray ray;
            // Start inside the plane's cell or outside the scene, aim inside the cell.
            Vec3f target, origin;
            for (int axis = 0; axis < 3; ++axis) {
                target[axis] = plane.cell.lo[axis] + unit(rng) * (plane.cell.hi[axis] - plane.cell.lo[axis]);
                origin[axis] = box.lo[axis] + (unit(rng) * 3.0f - 1.0f) * (box.hi[axis] - box.lo[axis]);
            }
            target[a] = origin[a] = plane.position;
            if (k == 4) origin[b] = box.hi[b] + 1.0f;  // on the plane outside the scene: nothing at t = 0
            Vec3f dir = target - origin;
            if (k == 4) dir[a] = sym(rng) * length(dir);  // starts on the plane and crosses it
            if (k == 5) {
                dir = Vec3f{0.0f};  // along one of the plane's axes
                dir[unit(rng) < 0.5f ? b : c] = unit(rng) < 0.5f ? 1.0f : -1.0f;
            }
            if (k < 4) dir[a] = k % 2 ? -0.0f : 0.0f;  // lies in the plane
            if (dot(dir, dir) == 0.0f) continue;
            ray.origin = origin;
            ray.dir = dir;
            rays.push_back(ray);
        }
    }
    return rays;
}

}  // namespace

TEST_CASE("closest hits agree with the double brute force on random soups") {
    for (const bool perfect : {false, true}) {
        CAPTURE(perfect);
        KdTreeOptions options;
        options.perfect_splits = perfect;
        for (const float size : {0.05f, 0.3f}) {
            CAPTURE(size);
            const Mesh mesh = random_soup(2000, 31, size);
            const KdTree tree = KdTree::build(mesh, options);
            const std::vector<Ray> rays = random_rays(mesh.bounds(), 3000, 32);
            check_agreement(tree, mesh, rays);
            check_agreement<TriangleTest::moller_trumbore>(tree, mesh, rays);
            check_any_hit(tree, mesh, rays);
        }
    }
}

TEST_CASE("rays lying in split planes, or starting on them, find what the brute force finds") {
    // Grid boxes: the planes hold triangles (box faces) and edges (of the faces across them), so a
    // ray in a plane hits edges of the triangles on both sides of it.
    const Mesh boxes = grid_boxes(60, 13);
    const Mesh soup = random_soup(1500, 14, 0.1f);
    for (const Mesh* mesh : {&boxes, &soup}) {
        for (const bool perfect : {false, true}) {
            CAPTURE(perfect);
            KdTreeOptions options;
            options.perfect_splits = perfect;
            const KdTree tree = KdTree::build(*mesh, options);
            const std::vector<Ray> rays = split_plane_rays(tree, 400, 15);
            CHECK(rays.size() > 1000);
            check_agreement(tree, *mesh, rays);
            check_any_hit(tree, *mesh, rays);
        }
    }
}

TEST_CASE("in-plane rays hit the edges of box faces that end on the plane") {
    // One box [0, 1]^3: the ray y = 1, z = 0.5 runs along the top face's plane and across the
    // side faces x = 0 and x = 1 at their top edges; the watertight test counts edge hits.
    const Mesh box = grid_boxes(1, 1, 1);
    const KdTree tree = KdTree::build(box);
    const Aabb b = tree.bounds();
    const float y = b.hi.y, z = 0.5f * (b.lo.z + b.hi.z);
    for (const float zero : {0.0f, -0.0f}) {
        const Ray ray{{b.lo.x - 1.0f, y, z}, {1.0f, zero, zero}};
        const Hit hit = tree.intersect(ray);
        const ReferenceHit ref = trace_reference(gather_triangles(box), ray);
        REQUIRE(ref.is_hit());
        CHECK(hit.is_hit());
        CHECK(hit.t == doctest::Approx(ref.t));
    }
}

TEST_CASE("axis-parallel rays with +0 and -0 components agree with the brute force") {
    const Mesh mesh = random_soup(1500, 41, 0.15f);
    const KdTree tree = KdTree::build(mesh);
    const std::vector<Ray> rays = random_rays(mesh.bounds(), 3000, 42, 1);  // all axis-parallel
    check_agreement(tree, mesh, rays);
    check_any_hit(tree, mesh, rays);
}

TEST_CASE("ray windows [tmin, tmax) are honoured") {
    const Mesh mesh = random_soup(1500, 51, 0.2f);
    const KdTree tree = KdTree::build(mesh);
    std::vector<Ray> rays = random_rays(mesh.bounds(), 2000, 52);
    std::mt19937 rng(53);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const float reach = 2.0f * length(mesh.bounds().extent());
    for (Ray& ray : rays) {
        ray.tmin = unit(rng) * reach;
        ray.tmax = ray.tmin + unit(rng) * reach;
    }
    check_agreement(tree, mesh, rays);
    check_any_hit(tree, mesh, rays);
    // A window ending exactly at the closest hit excludes it; one just past includes it.
    std::size_t checked = 0;
    for (Ray ray : random_rays(mesh.bounds(), 500, 54)) {
        const Hit hit = tree.intersect(ray);
        if (!hit.is_hit()) continue;
        ray.tmax = hit.t;
        CHECK(tree.intersect(ray).t >= hit.t);  // another triangle at the same t cannot count either
        CHECK(tree.intersect(ray).triangle != hit.triangle);
        ray.tmax = std::nextafter(hit.t, kInfinity);
        CHECK(tree.occluded(ray));
        ++checked;
    }
    CHECK(checked > 100);
}

TEST_CASE("the tree tests far fewer triangles than the brute force, and counts what it does") {
    const Mesh mesh = random_soup(20000, 61, 0.02f);
    const KdTree tree = KdTree::build(mesh);
    TraversalCounters counters;
    std::size_t hits = 0;
    const std::vector<Ray> rays = random_rays(mesh.bounds(), 500, 62);
    for (const Ray& ray : rays) hits += tree.intersect<TriangleTest::watertight>(ray, counters).is_hit();
    CHECK(hits > 100);
    CHECK(counters.nodes_visited > rays.size());
    CHECK(counters.triangles_tested > 0);
    CHECK(counters.triangles_tested < rays.size() * 200);  // the brute force: 20000 per ray
    TraversalCounters any;
    for (const Ray& ray : rays) (void)tree.occluded<TriangleTest::watertight>(ray, any);
    CHECK(any.triangles_tested <= counters.triangles_tested);
}

TEST_CASE("closest and any hits are right on every built-in scene") {
    for (const BuiltinSceneInfo& info : builtin_scenes_under_test()) {
        CAPTURE(info.name);
        const auto& [scene, tree] = builtin_kd(info.name);
        // The double brute force costs rays x triangles: about a hundred rays on the biggest scene.
        const std::size_t ray_count = std::clamp<std::size_t>(30'000'000 / (info.triangles + 1), 64, 2000);
        std::vector<Ray> rays = camera_rays(scene.camera, ray_count, 71);
        const std::vector<Ray> random = random_rays(scene.mesh.bounds(), ray_count / 2, 72);
        rays.insert(rays.end(), random.begin(), random.end());
        check_agreement(tree, scene.mesh, rays);
        check_any_hit(tree, scene.mesh, std::span<const Ray>(rays).first(rays.size() / 4));
    }
}
