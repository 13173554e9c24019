#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <tbb/task_arena.h>

#include "scenes/bezier_teapot.h"
#include "scenes/builtin.h"
#include "scenes/mesh_topology.h"

using namespace trident;
using namespace trident::testing;

namespace {

BuiltinSceneInfo info_of(const std::string& name) {
    for (const BuiltinSceneInfo& info : builtin_scenes())
        if (info.name == name) return info;
    FAIL("no built-in scene " << name);
    return {};
}

/// The million-triangle scene is generated once and shared by the test cases that read it.
const Scene& city() {
    static const Scene scene = make_builtin_scene("city");
    return scene;
}

/// What every built-in scene promises: its stated size, finite coordinates, no zero-area
/// triangles, a camera aimed into its bounds and a light.
void check_scene_basics(const Scene& scene, const BuiltinSceneInfo& info) {
    CHECK(scene.name == info.name);
    CHECK(scene.mesh.triangle_count() == info.triangles);
    CHECK(all_finite(scene.mesh));
    CHECK(zero_area_triangles(scene.mesh) == 0);
    std::uint32_t largest_index = 0;
    for (const IndexTriple& t : scene.mesh.triangles) largest_index = std::max({largest_index, t.v0, t.v1, t.v2});
    CHECK(largest_index < scene.mesh.vertex_count());
    const Aabb bounds = scene.mesh.bounds();
    CHECK(bounds.contains(scene.camera.target));
    CHECK(length(scene.camera.target - scene.camera.eye) > 0.0f);
    CHECK(length(cross(scene.camera.target - scene.camera.eye, scene.camera.up)) > 0.0f);
    CHECK(scene.camera.fov_y_deg > 0.0f);
    CHECK(scene.camera.fov_y_deg < 180.0f);
    REQUIRE(scene.light.has_value());
    CHECK(is_finite(scene.light->position));
}

bool open_edge_where(const Mesh& mesh, const std::pair<std::uint32_t, std::uint32_t>& e, auto&& predicate) {
    return predicate(mesh.vertex(e.first)) && predicate(mesh.vertex(e.second));
}

}  // namespace

TEST_CASE("the built-in scene list names four scenes and unknown names are refused by name") {
    const auto names = builtin_scene_names();
    REQUIRE(names.size() == 4);
    CHECK(names == std::vector<std::string>{"teapot", "asteroid", "hall", "city"});
    const auto infos = builtin_scenes();
    REQUIRE(infos.size() == names.size());
    for (std::size_t i = 0; i < infos.size(); ++i) {
        CHECK(infos[i].name == names[i]);
        CHECK(!infos[i].description.empty());
        CHECK(infos[i].description.find('\n') == std::string::npos);
        CHECK(is_builtin_scene(names[i]));
    }
    CHECK_FALSE(is_builtin_scene("sponza"));
    CHECK_FALSE(is_builtin_scene(""));
    try {
        make_builtin_scene("no-such-scene");
        FAIL("no exception");
    } catch (const std::invalid_argument& e) {
        CHECK(std::string(e.what()).find("no-such-scene") != std::string::npos);
    }
}

TEST_CASE("the scene sizes are the reference study's classes") {
    CHECK(info_of("teapot").triangles == 6320);  // 32 * 200 quads' triangles minus 80 at the poles
    CHECK(info_of("asteroid").triangles >= 100'000);
    CHECK(info_of("hall").triangles >= 250'000);
    CHECK(info_of("city").triangles >= 950'000);
    CHECK(info_of("city").triangles <= 1'100'000);
    CHECK(info_of("asteroid").closed);
    CHECK_FALSE(info_of("teapot").closed);
}

TEST_CASE("teapot: stated size, welded seams, open only at the lid gap and the spout and handle ends") {
    const Scene scene = make_builtin_scene("teapot");
    check_scene_basics(scene, info_of("teapot"));
    CHECK_FALSE(scene.mesh.bounds().contains(scene.camera.eye));
    std::size_t distinct = 0;
    welded_ids(scene.mesh, &distinct);
    CHECK(distinct == scene.mesh.vertex_count());  // every shared seam point is one vertex

    const EdgeTopology topology = edge_topology(scene.mesh);
    CHECK(topology.non_manifold_edges == 0);
    CHECK(topology.repeated_directed_edges == 0);  // Newell's patches are wound consistently
    // 10 segments per patch edge: the body's rim and the lid's edge (4 patches each) leave the
    // lid gap; spout and handle are tubes (2 patches round) open at both ends. The bottom seam
    // (body to Crow's bottom patches) repeats its control points in reverse and welds shut.
    std::size_t lid_gap = 0, spout = 0, handle = 0;
    for (const auto& e : topology.open_edges) {
        const auto at_lid_gap = [](const Vec3f& p) {
            const float r = std::sqrt(p.x * p.x + p.z * p.z);
            return p.y == 2.4f && r > 1.25f && r < 1.45f;
        };
        lid_gap += open_edge_where(scene.mesh, e, at_lid_gap) ? 1 : 0;
        spout += open_edge_where(scene.mesh, e, [](const Vec3f& p) { return p.x >= 1.7f; }) ? 1 : 0;
        handle += open_edge_where(scene.mesh, e, [](const Vec3f& p) { return p.x <= -1.5f; }) ? 1 : 0;
    }
    CHECK(lid_gap == 80);
    CHECK(spout == 40);
    CHECK(handle == 40);
    CHECK(topology.open_edges.size() == 160);
}

TEST_CASE("teapot triangle count formula matches the tessellation at every resolution") {
    for (std::uint32_t n : {kMinTeapotSegments, 3u, 7u, 10u, kMaxTeapotSegments}) {
        CAPTURE(n);
        const Mesh mesh = make_bezier_teapot(n);
        CHECK(mesh.triangle_count() == bezier_teapot_triangle_count(n));
        CHECK(mesh.triangle_count() == 64u * n * n - 8u * n);
        CHECK(zero_area_triangles(mesh) == 0);
        const EdgeTopology topology = edge_topology(mesh);
        // 16 open patch boundaries of n edges: rim and lid edge (4 patches each), spout and handle
        // ends (2 patches at each of 2 ends each).
        CHECK(topology.open_edges.size() == 16u * n);
        CHECK(topology.non_manifold_edges == 0);
        CHECK(topology.repeated_directed_edges == 0);
    }
    CHECK_THROWS_AS(make_bezier_teapot(kMinTeapotSegments - 1), std::invalid_argument);
    CHECK_THROWS_AS(bezier_teapot_triangle_count(kMaxTeapotSegments + 1), std::invalid_argument);
}

TEST_CASE("asteroid: stated size, watertight, consistently wound outwards, no duplicate vertices") {
    const Scene scene = make_builtin_scene("asteroid");
    check_scene_basics(scene, info_of("asteroid"));
    const EdgeTopology topology = edge_topology(scene.mesh);
    CHECK(topology.open_edges.empty());
    CHECK(topology.non_manifold_edges == 0);
    CHECK(topology.repeated_directed_edges == 0);
    CHECK(topology.edges * 2 == scene.mesh.triangle_count() * 3);
    std::size_t distinct = 0;
    welded_ids(scene.mesh, &distinct);
    CHECK(distinct == scene.mesh.vertex_count());
    CHECK(signed_volume(scene.mesh) > 0.0);
    // Outside the bounding box is outside the object; the light too.
    CHECK_FALSE(scene.mesh.bounds().contains(scene.camera.eye));
    CHECK_FALSE(scene.mesh.bounds().contains(scene.light->position));
}

TEST_CASE("hall: stated size, seen from inside, light inside") {
    const Scene scene = make_builtin_scene("hall");
    check_scene_basics(scene, info_of("hall"));
    CHECK(scene.mesh.bounds().contains(scene.camera.eye));
    CHECK(scene.mesh.bounds().contains(scene.light->position));
    CHECK(scene.camera.eye.y == doctest::Approx(1.7f));  // eye height
}

TEST_CASE("city: stated size, seen from street level") {
    check_scene_basics(city(), info_of("city"));
    CHECK(city().mesh.bounds().contains(city().camera.eye));
    CHECK(city().camera.eye.y < 2.0f);
}

TEST_CASE("generation is deterministic: the same meshes twice and on one thread") {
    for (const std::string name : {"teapot", "asteroid", "hall"}) {
        CAPTURE(name);
        const Scene first = make_builtin_scene(name);
        const Scene again = make_builtin_scene(name);
        Scene single_thread;
        tbb::task_arena(1).execute([&] { single_thread = make_builtin_scene(name); });
        CHECK(identical(first.mesh, again.mesh));
        CHECK(identical(first.mesh, single_thread.mesh));
        CHECK(first.camera.eye == single_thread.camera.eye);
    }
    Scene single_thread_city;
    tbb::task_arena(1).execute([&] { single_thread_city = make_builtin_scene("city"); });
    CHECK(identical(city().mesh, single_thread_city.mesh));
}
