#include <doctest/doctest.h>

#include <numbers>
#include <stdexcept>

#include "scenes/affine.h"
#include "scenes/closed_teapot.h"
#include "scenes/gradient_noise.h"
#include "scenes/hash_random.h"
#include "scenes/mesh_builder.h"
#include "scenes/mesh_topology.h"

using namespace trident;
using namespace trident::testing;

namespace {

Mesh build_one(Shape shape, const Affine& placement = {}) {
    MeshBuilder b;
    b.add(std::move(shape), placement);
    Mesh mesh = b.build();
    REQUIRE(mesh.vertex_count() == b.vertex_count());
    REQUIRE(mesh.triangle_count() == b.triangle_count());
    return mesh;
}

/// Closed, consistently wound outwards, no zero-area triangles, no repeated vertex.
void check_solid(const Mesh& mesh) {
    const EdgeTopology topology = edge_topology(mesh);
    CHECK(topology.open_edges.empty());
    CHECK(topology.non_manifold_edges == 0);
    CHECK(topology.repeated_directed_edges == 0);
    CHECK(zero_area_triangles(mesh) == 0);
    CHECK(signed_volume(mesh) > 0.0);
    std::size_t distinct = 0;
    welded_ids(mesh, &distinct);
    CHECK(distinct == mesh.vertex_count());
}

}  // namespace

TEST_CASE("splitmix64 matches the published sequence, so scenes are the same on every platform") {
    // The first output of Vigna's reference splitmix64 seeded with 0.
    CHECK(splitmix64(0) == 0xE220A8397B1DCDAFull);
    HashRandom a(7), b(7), c(8);
    bool differs = false;
    for (int i = 0; i < 100; ++i) {
        const float u = a.uniform();
        CHECK(u == b.uniform());
        CHECK(u >= 0.0f);
        CHECK(u < 1.0f);
        differs = differs || u != c.uniform();
        CHECK(a.below(5) < 5u);
        b.below(5);
        c.below(5);
    }
    CHECK(differs);
    CHECK(unit_float(~0ull) < 1.0f);
}

TEST_CASE("gradient noise is zero on the lattice, bounded, and fixed by its seed") {
    CHECK(gradient_noise({3.0f, -2.0f, 5.0f}, 1) == 0.0f);
    bool seeds_differ = false;
    for (int i = 0; i < 500; ++i) {
        const Vec3f p{0.37f * float(i), -0.11f * float(i), 0.05f * float(i) + 0.3f};
        const float n = gradient_noise(p, 1);
        CHECK(std::abs(n) <= 1.0f);
        CHECK(std::abs(fractal_noise(p, 4, 1)) <= 1.0f);
        CHECK(n == gradient_noise(p, 1));
        seeds_differ = seeds_differ || n != gradient_noise(p, 2);
    }
    CHECK(seeds_differ);
}

TEST_CASE("a box is a closed outward-wound solid with its exact volume") {
    const Mesh mesh = build_one(Box{{-1.0f, 0.0f, 2.0f}, {2.0f, 0.5f, 3.0f}});
    CHECK(mesh.triangle_count() == 12);
    check_solid(mesh);
    CHECK(signed_volume(mesh) == doctest::Approx(1.5));
}

TEST_CASE("lathes with caps, poles, flutes and loops are closed solids of the expected size") {
    SUBCASE("cylinder") {
        const Mesh mesh = build_one(cylinder(0.5f, 1.0f, 3.0f, 64));
        check_solid(mesh);
        CHECK(signed_volume(mesh) == doctest::Approx(std::numbers::pi * 0.25 * 2.0).epsilon(0.01));
    }
    SUBCASE("sphere from a profile with a pole at each end") {
        Lathe sphere{{}, 48};
        for (int i = 0; i <= 24; ++i) {
            const double a = -std::numbers::pi / 2 + std::numbers::pi * i / 24;
            sphere.profile.push_back({i == 0 || i == 24 ? 0.0f : float(std::cos(a)), float(std::sin(a))});
        }
        const Mesh mesh = build_one(sphere);
        check_solid(mesh);
        CHECK(signed_volume(mesh) == doctest::Approx(4.0 / 3.0 * std::numbers::pi).epsilon(0.02));
    }
    SUBCASE("fluted column shaft") {
        check_solid(build_one(Lathe{{{0.5f, 0.0f}, {0.45f, 2.0f}, {0.4f, 4.0f}}, 96, false, 24, 0.05f}));
    }
    SUBCASE("torus") {
        const Mesh mesh = build_one(torus(2.0f, 0.5f, 1.0f, 96, 32));
        check_solid(mesh);
        CHECK(signed_volume(mesh) == doctest::Approx(2.0 * std::numbers::pi * std::numbers::pi * 2.0 * 0.25).epsilon(0.01));
    }
}

TEST_CASE("round and square-shouldered arches are closed solids") {
    const Mesh round = build_one(Arch{1.0f, 1.5f, 0.4f, 32, false});
    check_solid(round);
    CHECK(signed_volume(round) == doctest::Approx(0.5 * std::numbers::pi * (1.5 * 1.5 - 1.0) * 0.4).epsilon(0.01));
    const Mesh square = build_one(Arch{1.0f, 1.5f, 0.4f, 32, true});
    check_solid(square);
    CHECK(signed_volume(square) == doctest::Approx((3.0 * 1.5 - 0.5 * std::numbers::pi) * 0.4).epsilon(0.01));
}

TEST_CASE("geodesic spheres are closed at every frequency and approach the unit sphere") {
    for (std::uint32_t f : {1u, 2u, 3u, 7u, 20u}) {
        CAPTURE(f);
        const Mesh mesh = build_one(GeodesicSphere{f});
        CHECK(mesh.triangle_count() == 20u * f * f);
        check_solid(mesh);
        for (std::uint32_t i = 0; i < mesh.vertex_count(); ++i) CHECK(length(mesh.vertex(i)) == doctest::Approx(1.0f));
    }
    CHECK(signed_volume(build_one(GeodesicSphere{20})) == doctest::Approx(4.0 / 3.0 * std::numbers::pi).epsilon(0.01));
}

TEST_CASE("placements move parts and keep their winding; mirroring placements are refused") {
    const Affine place =
        translation({5.0f, 0.0f, 0.0f}) * rotation_y(0.3f) * rotation_x(1.1f) * scaling({2.0f, 1.0f, 0.5f});
    const Mesh mesh = build_one(Box{{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}}, place);
    check_solid(mesh);
    CHECK(signed_volume(mesh) == doctest::Approx(1.0));
    CHECK(place.apply({0.0f, 0.0f, 0.0f}) == Vec3f{5.0f, 0.0f, 0.0f});
    const Affine tilt = y_along({1.0f, 2.0f, -0.5f});
    CHECK(tilt.determinant() == doctest::Approx(1.0f));
    const Vec3f up = tilt.apply_linear({0.0f, 1.0f, 0.0f});
    CHECK(dot(up, normalize(Vec3f{1.0f, 2.0f, -0.5f})) == doctest::Approx(1.0f));
    MeshBuilder b;
    CHECK_THROWS_AS(b.add(Box{{0, 0, 0}, {1, 1, 1}}, scaling({-1.0f, 1.0f, 1.0f})), std::invalid_argument);
    CHECK_THROWS_AS(b.add(Box{{0, 0, 0}, {1, 1, 1}}, scaling({0.0f, 1.0f, 1.0f})), std::invalid_argument);
    CHECK(b.part_count() == 0);
}

TEST_CASE("parts keep their order and their own vertex ranges in the built mesh") {
    MeshBuilder b;
    b.add(Box{{0, 0, 0}, {1, 1, 1}});
    b.add(GeodesicSphere{2}, translation({3.0f, 0.0f, 0.0f}));
    b.add(Box{{0, 0, 0}, {1, 1, 1}}, translation({-3.0f, 0.0f, 0.0f}));
    const Mesh mesh = b.build();
    REQUIRE(mesh.triangle_count() == 12 + 80 + 12);
    for (std::size_t t = 0; t < 12; ++t) {
        CHECK(triangle_of(mesh, t).centroid().x >= 0.0f);
        CHECK(triangle_of(mesh, t).centroid().x <= 1.0f);
    }
    for (std::size_t t = 12; t < 92; ++t) CHECK(triangle_of(mesh, t).centroid().x > 2.0f);
    for (std::size_t t = 92; t < 104; ++t) CHECK(triangle_of(mesh, t).centroid().x <= -2.0f);
    check_solid(mesh);
}

TEST_CASE("the closed teapot-like mesh is closed, outward wound and free of zero-area triangles") {
    for (std::uint32_t segments : {8u, 48u, 200u}) {
        CAPTURE(segments);
        const Mesh mesh = make_closed_teapot_like_mesh(segments);
        check_solid(mesh);
        CHECK(mesh.bounds().contains(Vec3f{0.0f, 1.5f, 0.0f}));
    }
    CHECK_THROWS_AS(make_closed_teapot_like_mesh(7), std::invalid_argument);
}
