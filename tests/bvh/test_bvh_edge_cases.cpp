// Degenerate inputs (no triangles, one, all identical, all in one plane, zero-area), the ray
// interval [tmin, tmax), and option validation.
#include <doctest/doctest.h>

#include <cstring>
#include <stdexcept>

#include "bvh_test_helpers.h"
#include "support/random_scenes.h"
#include "support/reference_check.h"

using namespace trident;
using namespace trident::testing;

namespace {

void add_triangle(Mesh& mesh, Vec3f a, Vec3f b, Vec3f c) {
    mesh.add_triangle(mesh.add_vertex(a), mesh.add_vertex(b), mesh.add_vertex(c));
}

void require_matches_reference(const Bvh& bvh, const Mesh& mesh, const std::vector<Ray>& rays) {
    const std::vector<Triangle> triangles = gather_triangles(mesh);
    require_agreement(compare_with_reference<Hit>(triangles, rays, trace_all(bvh, rays)));
    for (const Ray& ray : rays) CHECK(bvh.occluded(ray) == occluded_reference(triangles, ray));
}

}  // namespace

TEST_CASE("an empty mesh builds an empty tree that every ray misses") {
    const Mesh mesh;
    for (BvhBuilder builder : {BvhBuilder::binned_sah, BvhBuilder::sweep_sah, BvhBuilder::spatial_sah}) {
        BvhOptions options;
        options.builder = builder;
        const Bvh bvh = Bvh::build(mesh, options);
        check_invariants(bvh, mesh);
        CHECK(bvh.stats().nodes == 0);
        CHECK(bvh.stats().sah_cost == 0.0);
        for (const Ray& ray : random_rays(Aabb{{-1, -1, -1}, {1, 1, 1}}, 50, 1)) {
            const Hit hit = bvh.intersect(ray);
            CHECK_FALSE(hit.is_hit());
            CHECK(hit.t == kInfinity);
            CHECK_FALSE(bvh.occluded(ray));
        }
    }
}

TEST_CASE("one triangle is a single leaf, hit and missed correctly") {
    Mesh mesh;
    add_triangle(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    const Bvh bvh = Bvh::build(mesh);
    check_invariants(bvh, mesh);
    CHECK(bvh.stats().nodes == 1);
    const Hit hit = bvh.intersect(Ray{{0.25f, 0.25f, 1.0f}, {0, 0, -1}});
    CHECK(hit.triangle == 0);
    CHECK(hit.t == doctest::Approx(1.0f));
    CHECK_FALSE(bvh.intersect(Ray{{0.75f, 0.75f, 1.0f}, {0, 0, -1}}).is_hit());
}

TEST_CASE("identical triangles (every centroid equal) fall back to median splits and leaves within the cap") {
    Mesh mesh;
    for (int i = 0; i < 500; ++i) add_triangle(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    for (BvhBuilder builder : {BvhBuilder::binned_sah, BvhBuilder::sweep_sah, BvhBuilder::spatial_sah}) {
        BvhOptions options;
        options.builder = builder;
        const Bvh bvh = Bvh::build(mesh, options);
        check_invariants(bvh, mesh);
        CHECK(bvh.stats().max_leaf_size <= 8);
        require_matches_reference(bvh, mesh, random_rays(mesh.bounds(), 100, 2));
    }
}

TEST_CASE("triangles all in one plane (zero extent on an axis) and nested ones sharing a centroid") {
    const Mesh soup = random_soup(3000, 5, 0.1f);
    Mesh flat;
    for (std::size_t i = 0; i < soup.triangle_count(); ++i) {
        Triangle t = triangle_of(soup, i);
        t.a.z = t.b.z = t.c.z = 0.5f;
        add_triangle(flat, t.a, t.b, t.c);
    }
    Mesh nested;  // same centroid, growing sizes: only a median split can separate them
    for (int i = 1; i <= 300; ++i) {
        const float s = 0.01f * float(i);
        add_triangle(nested, {-s, -s, 0}, {2 * s, -s, 0}, {-s, 2 * s, 0});
    }
    for (const Mesh* mesh : {&flat, &nested})
        for (BvhBuilder builder : {BvhBuilder::binned_sah, BvhBuilder::sweep_sah, BvhBuilder::spatial_sah}) {
            BvhOptions options;
            options.builder = builder;
            const Bvh bvh = Bvh::build(*mesh, options);
            check_invariants(bvh, *mesh);
            std::vector<Ray> rays = random_rays(mesh->bounds(), 300, 6);
            for (const Ray& r : random_rays(mesh->bounds(), 100, 7, 1)) rays.push_back(r);  // all axis-parallel
            require_matches_reference(bvh, *mesh, rays);
        }
}

TEST_CASE("zero-area triangles are kept but never hit") {
    Mesh mesh;
    for (int i = 0; i < 100; ++i) {
        const float x = float(i) * 0.1f;
        add_triangle(mesh, {x, 0, 0}, {x, 0, 0}, {x, 0, 0});                 // a point
        add_triangle(mesh, {x, 0, 0}, {x + 0.05f, 0, 0}, {x + 0.1f, 0, 0});  // a segment
    }
    const Bvh bvh = Bvh::build(mesh);
    check_invariants(bvh, mesh);
    for (const Ray& ray : random_rays(Aabb{{-1, -1, -1}, {11, 1, 1}}, 200, 8)) CHECK_FALSE(bvh.intersect(ray).is_hit());
}

TEST_CASE("the ray interval is honoured: hits count from tmin inclusive to tmax exclusive") {
    Mesh mesh;  // a stack of squares at z = 1, 2, 3, 4 (two triangles each)
    for (int k = 1; k <= 4; ++k) {
        const float z = float(k);
        add_triangle(mesh, {-1, -1, z}, {1, -1, z}, {1, 1, z});
        add_triangle(mesh, {-1, -1, z}, {1, 1, z}, {-1, 1, z});
    }
    BvhOptions options;
    options.max_leaf_size = 1;
    const Bvh bvh = Bvh::build(mesh, options);
    const Vec3f origin{0.3f, -0.2f, 0.0f}, up{0, 0, 1};
    CHECK(bvh.intersect(Ray{origin, up}).t == 1.0f);
    CHECK(bvh.intersect(Ray{origin, up, 1.0f}).t == 1.0f);  // tmin is inclusive
    CHECK(bvh.intersect(Ray{origin, up, 1.5f}).t == 2.0f);
    CHECK(bvh.intersect(Ray{origin, up, 3.5f, 10.0f}).t == 4.0f);
    CHECK_FALSE(bvh.intersect(Ray{origin, up, 0.0f, 1.0f}).is_hit());  // tmax is exclusive
    CHECK_FALSE(bvh.intersect(Ray{origin, up, 4.5f}).is_hit());
    CHECK_FALSE(bvh.intersect(Ray{origin, up, 1.5f, 2.0f}).is_hit());
    CHECK(bvh.occluded(Ray{origin, up, 1.5f, 2.0001f}));
    CHECK_FALSE(bvh.occluded(Ray{origin, up, 1.5f, 2.0f}));
    CHECK_FALSE(bvh.occluded(Ray{origin, up, 4.0001f}));
    const Hit hit = bvh.intersect(Ray{origin, up, 2.5f});
    CHECK(hit.t == 3.0f);
    CHECK(triangle_of(mesh, hit.triangle).a.z == 3.0f);  // the id is the file-order index
}

TEST_CASE("spatial splits cut large triangles among small ones: more references, a lower SAH, the same hits") {
    const Mesh mesh = soup_with_large_triangles(3000, 30, 21);
    BvhOptions spatial;
    spatial.builder = BvhBuilder::spatial_sah;
    const Bvh objects = Bvh::build(mesh), cut = Bvh::build(mesh, spatial);
    check_invariants(cut, mesh);
    CHECK(cut.stats().references > mesh.triangle_count());
    CHECK(cut.stats().references <= std::size_t(double(mesh.triangle_count()) * (1.0 + spatial.spatial_split_budget)));
    CHECK(cut.stats().sah_cost < 0.95 * objects.stats().sah_cost);
    std::vector<Ray> rays = random_rays(mesh.bounds(), 1500, 22);
    for (const Ray& r : random_rays(mesh.bounds(), 300, 23, 1)) rays.push_back(r);  // axis-parallel, along the planes
    require_matches_reference(cut, mesh, rays);
    // No budget: object splits only, each triangle once.
    spatial.spatial_split_budget = 0.0f;
    const Bvh uncut = Bvh::build(mesh, spatial);
    check_invariants(uncut, mesh);
    CHECK(uncut.stats().references == mesh.triangle_count());
    CHECK(cut.stats().sah_cost < 0.95 * uncut.stats().sah_cost);
    // Where no node may take a spatial split, the builder hands the whole tree to the binned one:
    // the binned build's tree, node for node and in the same leaf order.
    REQUIRE(uncut.nodes().size() == objects.nodes().size());
    CHECK(std::memcmp(uncut.nodes().data(), objects.nodes().data(), objects.nodes().size_bytes()) == 0);
    REQUIRE(uncut.leaf_triangle_ids().size() == objects.leaf_triangle_ids().size());
    CHECK(std::memcmp(uncut.leaf_triangle_ids().data(), objects.leaf_triangle_ids().data(),
                      objects.leaf_triangle_ids().size_bytes()) == 0);
}

TEST_CASE("invalid options are rejected with a message naming the field") {
    auto rejects = [](auto change, const char* field) {
        BvhOptions options;
        change(options);
        CAPTURE(field);
        try {
            options.validate();
            FAIL("accepted");
        } catch (const std::invalid_argument& e) {
            CHECK(std::string(e.what()).find(field) != std::string::npos);
        }
        CHECK_THROWS_AS(Bvh::build(random_soup(10, 1), options), std::invalid_argument);
    };
    rejects([](BvhOptions& o) { o.bin_count = 7; }, "bin_count");
    rejects([](BvhOptions& o) { o.bin_count = 65; }, "bin_count");
    rejects([](BvhOptions& o) { o.large_node_bin_count = 16; }, "large_node_bin_count");
    rejects([](BvhOptions& o) { o.large_node_bin_count = 257; }, "large_node_bin_count");
    rejects([](BvhOptions& o) { o.max_leaf_size = 0; }, "max_leaf_size");
    rejects([](BvhOptions& o) { o.max_leaf_size = 256; }, "max_leaf_size");
    rejects([](BvhOptions& o) { o.traversal_cost = -1.0f; }, "traversal_cost");
    rejects([](BvhOptions& o) { o.intersection_cost = 0.0f; }, "intersection_cost");
    rejects([](BvhOptions& o) { o.builder = BvhBuilder(7); }, "builder");
    rejects([](BvhOptions& o) { o.spatial_split_budget = -0.5f; }, "spatial_split_budget");
    rejects([](BvhOptions& o) { o.spatial_split_budget = 5.0f; }, "spatial_split_budget");
    for (int bins : {8, 64}) {
        BvhOptions options;
        options.bin_count = options.large_node_bin_count = bins;
        CHECK_NOTHROW(options.validate());
    }
    CHECK_NOTHROW(BvhOptions::study().validate());
}
