// BVH traversal against the double-precision brute force: closest hits, any hits, and the
// Möller–Trumbore variant, on random soups and on the built-in scenes.
#include <doctest/doctest.h>

#include <string>

#include "bvh_test_helpers.h"
#include "support/random_scenes.h"
#include "support/reference_check.h"
#include "support/sanitizer_workload.h"

using namespace trident;
using namespace trident::testing;

namespace {

struct NamedOptions {
    const char* name;
    BvhOptions options;
};

std::vector<NamedOptions> option_variants() {
    BvhOptions sweep;
    sweep.builder = BvhBuilder::sweep_sah;
    BvhOptions tiny_leaves;
    tiny_leaves.max_leaf_size = 1;
    tiny_leaves.bin_count = 8;
    tiny_leaves.large_node_bin_count = 8;
    return {{"default", {}}, {"study", BvhOptions::study()}, {"sweep", sweep}, {"max leaf 1, 8 bins", tiny_leaves}};
}

void require_closest_hits_match_reference(const Bvh& bvh, const Mesh& mesh, const std::vector<Ray>& rays) {
    const std::vector<Triangle> triangles = gather_triangles(mesh);
    const std::vector<Hit> hits = trace_all(bvh, rays);
    require_agreement(compare_with_reference<Hit>(triangles, rays, hits));
}

void require_any_hit_agrees(const Bvh& bvh, const std::vector<Ray>& rays) {
    std::size_t disagreements = 0;
    for (const Ray& ray : rays) disagreements += bvh.occluded(ray) != bvh.intersect(ray).is_hit();
    CHECK(disagreements == 0);
}

/// Möller–Trumbore is not watertight, so it may differ on rays through edges: almost all agree.
void require_moller_trumbore_mostly_agrees(const Bvh& bvh, const std::vector<Ray>& rays) {
    std::size_t disagreements = 0;
    NoCounters counters;
    for (const Ray& ray : rays)
        disagreements +=
            bvh.intersect<TriangleTest::moller_trumbore>(ray, counters).is_hit() != bvh.intersect(ray).is_hit();
    CHECK(double(disagreements) <= 0.01 * double(rays.size()));
    std::size_t occluded_disagreements = 0;
    for (const Ray& ray : rays)
        occluded_disagreements += bvh.occluded<TriangleTest::moller_trumbore>(ray, counters) !=
                                  bvh.intersect<TriangleTest::moller_trumbore>(ray, counters).is_hit();
    CHECK(occluded_disagreements == 0);
}

}  // namespace

TEST_CASE("closest hits equal the double-precision brute force on random soups, for every builder setting") {
    for (const NamedOptions& variant : option_variants())
        for (std::size_t count : {1u, 2u, 13u, 200u, 3000u})
            for (std::uint32_t seed : {1u, 2u, 3u}) {
                CAPTURE(variant.name);
                CAPTURE(count);
                CAPTURE(seed);
                const Mesh mesh = random_soup(count, seed, count > 1000 ? 0.05f : 0.3f);
                const Bvh bvh = Bvh::build(mesh, variant.options);
                const std::vector<Ray> rays = random_rays(mesh.bounds(), 200, seed + 100);
                require_closest_hits_match_reference(bvh, mesh, rays);
                require_any_hit_agrees(bvh, rays);
            }
}

TEST_CASE("Möller–Trumbore traversal agrees with the watertight one on hit or miss for almost all rays") {
    const Mesh mesh = random_soup(5000, 11, 0.05f);
    const Bvh bvh = Bvh::build(mesh);
    require_moller_trumbore_mostly_agrees(bvh, random_rays(mesh.bounds(), 2000, 12));
}

TEST_CASE("closest and any hits are right on every built-in scene, for camera rays and random rays") {
    for (const BuiltinSceneInfo& info : builtin_scenes_under_test()) {
        CAPTURE(info.name);
        const Scene& scene = builtin_scene(info.name);
        const Bvh& bvh = builtin_bvh(info.name);
        // The double brute force costs a pass over every triangle per ray: fewer rays for big scenes.
        const std::size_t ray_count = info.triangles > 500000 ? 16 : info.triangles > 100000 ? 48 : 300;
        std::vector<Ray> rays = camera_rays(scene.camera, ray_count, 5);
        const std::vector<Ray> random = random_rays(scene.mesh.bounds(), ray_count, 6);
        rays.insert(rays.end(), random.begin(), random.end());
        require_closest_hits_match_reference(bvh, scene.mesh, rays);
        // More rays for the checks that need no reference.
        const std::vector<Ray> many = camera_rays(scene.camera, 1000, 8);
        require_any_hit_agrees(bvh, many);
        require_moller_trumbore_mostly_agrees(bvh, many);
    }
}

TEST_CASE("rays with a zero direction component starting exactly on box planes find the reference hits") {
    // An axis-aligned lattice of unit right triangles in the planes x = i, y = j and z = k: every
    // node box has integer planes, and rays start on them with +0 or -0 direction components.
    Mesh mesh;
    for (int i = 0; i <= 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 4; ++k) {
                const float a = float(i), b = float(j), c = float(k);
                auto tri = [&](Vec3f p, Vec3f q, Vec3f r) {
                    mesh.add_triangle(mesh.add_vertex(p), mesh.add_vertex(q), mesh.add_vertex(r));
                };
                tri({a, b, c}, {a, b + 1, c}, {a, b, c + 1});
                tri({b, a, c}, {b, a, c + 1}, {b + 1, a, c});
                tri({b, c, a}, {b + 1, c, a}, {b, c + 1, a});
            }
    for (int max_leaf : {1, 8}) {
        BvhOptions options;
        options.max_leaf_size = max_leaf;
        const Bvh bvh = Bvh::build(mesh, options);
        std::vector<Ray> rays;
        for (int axis = 0; axis < 3; ++axis)
            for (float sign : {1.0f, -1.0f})
                for (float zero : {0.0f, -0.0f})
                    for (int u = 0; u <= 8; ++u)
                        for (int v = 0; v <= 8; ++v)
                            for (float tmin : {0.0f, 0.5f, 2.5f}) {
                                Ray ray;
                                ray.dir = Vec3f{zero, zero, zero};
                                ray.dir[axis] = sign;
                                ray.origin[axis] = sign > 0 ? -1.0f : 5.0f;
                                ray.origin[(axis + 1) % 3] = 0.5f * float(u);  // on a plane when u is even
                                ray.origin[(axis + 2) % 3] = 0.5f * float(v);
                                ray.tmin = tmin;
                                rays.push_back(ray);
                            }
        CAPTURE(max_leaf);
        require_closest_hits_match_reference(bvh, mesh, rays);
        require_any_hit_agrees(bvh, rays);
    }
}
