#pragma once
// Shared by the BVH tests: tracing a batch of rays, the built-in scenes and camera rays for them,
// and the structural invariants every flattened BVH must satisfy.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "accel/bvh/bvh.h"
#include "accel/bvh/bvh_stats.h"
#include "core/scene.h"
#include "scenes/builtin.h"
#include "support/camera_rays.h"

namespace trident::testing {

template <TriangleTest Test = TriangleTest::watertight>
std::vector<Hit> trace_all(const Bvh& bvh, const std::vector<Ray>& rays) {
    std::vector<Hit> hits;
    hits.reserve(rays.size());
    NoCounters counters;
    for (const Ray& ray : rays) hits.push_back(bvh.intersect<Test>(ray, counters));
    return hits;
}

/// The built-in scene and its BVH (default options), each made once per test run: several tests
/// use the big ones.
inline const Scene& builtin_scene(const std::string& name) {
    static std::map<std::string, Scene> cache;
    auto it = cache.find(name);
    if (it == cache.end()) it = cache.emplace(name, make_builtin_scene(name)).first;
    return it->second;
}
inline const Bvh& builtin_bvh(const std::string& name) {
    static std::map<std::string, Bvh> cache;
    auto it = cache.find(name);
    if (it == cache.end()) it = cache.emplace(name, Bvh::build(builtin_scene(name).mesh)).first;
    return it->second;
}

/// Every structural promise of the flattened layout, checked against the mesh it was built from.
/// Violations are counted and checked once per kind, so big scenes stay fast to check.
inline void check_invariants(const Bvh& bvh, const Mesh& mesh) {
    const auto nodes = bvh.nodes();
    const auto triangles = bvh.leaf_triangles();
    const auto ids = bvh.leaf_triangle_ids();
    const std::size_t n = mesh.triangle_count();
    // Spatial splits put a cut triangle in each leaf its pieces reached: more slots than triangles.
    const bool spatial = bvh.options().builder == BvhBuilder::spatial_sah;
    const std::size_t slots = ids.size();
    REQUIRE(triangles.size() == slots);
    REQUIRE((spatial ? slots >= n : slots == n));
    REQUIRE(nodes.empty() == (n == 0));

    // Leaf-order slots hold each file-order triangle exactly once (at least once with spatial
    // splits), with its exact corners.
    std::vector<int> seen_id(n, 0);
    std::size_t wrong_corners = 0;
    for (std::size_t i = 0; i < slots; ++i) {
        if (ids[i] >= n) FAIL("leaf slot ", i, " holds id ", ids[i], " of ", n);
        ++seen_id[ids[i]];
        const Triangle expected = triangle_of(mesh, ids[i]);
        wrong_corners +=
            !(triangles[i].a == expected.a && triangles[i].b == expected.b && triangles[i].c == expected.c);
    }
    CHECK(wrong_corners == 0);
    if (spatial)
        CHECK(std::count(seen_id.begin(), seen_id.end(), 0) == 0);
    else
        CHECK(std::count(seen_id.begin(), seen_id.end(), 1) == std::ptrdiff_t(n));

    // Depth-first walk: every node is visited at its own index (left child right after its
    // parent, right child after the whole left subtree); leaves tile the slots exactly once. A
    // leaf's box holds its triangles (with spatial splits, the pieces it was given: it meets each
    // triangle's box) and no triangle twice.
    std::vector<int> slot_covered(slots, 0);
    std::size_t next = 0, leaves = 0, references = 0, max_leaf = 0, max_depth = 0;
    std::size_t out_of_order = 0, child_outside_parent = 0, triangle_outside_leaf = 0, oversized_leaves = 0,
                bad_axes = 0, repeated_in_leaf = 0;
    auto walk = [&](auto&& self, std::uint32_t index, std::size_t depth, const Aabb* parent) -> void {
        out_of_order += index != next;
        if (index >= nodes.size()) FAIL("node index ", index, " of ", nodes.size());
        next = index + 1;
        const BvhNode& node = nodes[index];
        max_depth = std::max(max_depth, depth);
        if (parent) child_outside_parent += !parent->contains(node.bounds);
        if (node.is_leaf()) {
            ++leaves;
            references += node.triangle_count();
            max_leaf = std::max<std::size_t>(max_leaf, node.triangle_count());
            oversized_leaves += node.triangle_count() > std::uint32_t(bvh.options().max_leaf_size);
            if (node.first_triangle() + node.triangle_count() > slots)
                FAIL("leaf ", index, " runs past the triangles");
            for (std::uint32_t i = node.first_triangle(); i < node.first_triangle() + node.triangle_count(); ++i) {
                ++slot_covered[i];
                const Aabb box = triangles[i].bounds();
                triangle_outside_leaf += spatial ? Aabb{max(box.lo, node.bounds.lo), min(box.hi, node.bounds.hi)}.is_empty()
                                                 : !node.bounds.contains(box);
                repeated_in_leaf += std::count(ids.begin() + node.first_triangle(), ids.begin() + i, ids[i]) != 0;
            }
            return;
        }
        bad_axes += node.split_axis() >= 3;
        self(self, index + 1, depth + 1, &node.bounds);
        out_of_order += node.right_child() != next;
        self(self, node.right_child(), depth + 1, &node.bounds);
    };
    if (!nodes.empty()) walk(walk, 0, 0, nullptr);
    CHECK(out_of_order == 0);
    CHECK(next == nodes.size());
    CHECK(child_outside_parent == 0);
    CHECK(triangle_outside_leaf == 0);
    CHECK(oversized_leaves == 0);
    CHECK(bad_axes == 0);
    CHECK(repeated_in_leaf == 0);
    CHECK(std::count(slot_covered.begin(), slot_covered.end(), 1) == std::ptrdiff_t(slots));
    CHECK(max_depth <= kBvhMaxDepth);

    const AccelStats& stats = bvh.stats();
    CHECK(stats.structure == "bvh2");
    CHECK(stats.triangles == n);
    CHECK(stats.nodes == nodes.size());
    CHECK(stats.leaves == leaves);
    CHECK(stats.empty_leaves == 0);
    CHECK(stats.references == references);
    CHECK(stats.references == slots);
    CHECK(stats.max_leaf_size == max_leaf);
    CHECK(stats.max_depth == max_depth);
    CHECK(stats.mean_leaf_size == doctest::Approx(leaves ? double(references) / double(leaves) : 0.0));
    CHECK(stats.bytes == nodes.size() * sizeof(BvhNode) + slots * (sizeof(Triangle) + sizeof(TriangleId)));
    CHECK(stats.sah_cost == bvh_sah_cost(nodes, bvh.options().traversal_cost, bvh.options().intersection_cost));
    CHECK(stats.build_ms >= 0.0);
}

/// A lattice of unit right triangles in the planes x = i, y = j and z = k (as in
/// test_bvh_traversal.cpp): node boxes with integer planes, triangles sharing edges.
inline Mesh axis_lattice() {
    Mesh mesh;
    auto tri = [&](Vec3f p, Vec3f q, Vec3f r) {
        mesh.add_triangle(mesh.add_vertex(p), mesh.add_vertex(q), mesh.add_vertex(r));
    };
    for (int i = 0; i <= 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 4; ++k) {
                const float a = float(i), b = float(j), c = float(k);
                tri({a, b, c}, {a, b + 1, c}, {a, b, c + 1});
                tri({b, a, c}, {b, a, c + 1}, {b + 1, a, c});
                tri({b, c, a}, {b + 1, c, a}, {b, c + 1, a});
            }
    return mesh;
}

/// Axis-parallel rays starting on the lattice's planes (half-integer steps) with +0 and -0 in the
/// other components, several tmin; consecutive rays share their direction.
inline std::vector<Ray> rays_on_lattice_planes() {
    std::vector<Ray> rays;
    for (int axis = 0; axis < 3; ++axis)
        for (float sign : {1.0f, -1.0f})
            for (float zero : {0.0f, -0.0f})
                for (float tmin : {0.0f, 2.5f})
                    for (int u = 0; u <= 8; ++u)
                        for (int v = 0; v <= 8; ++v) {
                            Ray ray;
                            ray.dir = Vec3f{zero, zero, zero};
                            ray.dir[axis] = sign;
                            ray.origin[axis] = sign > 0 ? -1.0f : 5.0f;
                            ray.origin[(axis + 1) % 3] = 0.5f * float(u);
                            ray.origin[(axis + 2) % 3] = 0.5f * float(v);
                            ray.tmin = tmin;
                            rays.push_back(ray);
                        }
    return rays;
}

}  // namespace trident::testing
