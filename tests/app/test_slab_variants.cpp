// The robust and the fast slab test (core/slab_test.h) threaded through every structure: on
// ordinary camera rays they agree; on rays running inside shared box faces the robust test never
// loses a hit the brute force (which tests no boxes) finds, while the fast one may.
#include <doctest/doctest.h>

#include <cstddef>
#include <string>
#include <vector>

#include "accel/any_accel.h"
#include "camera/camera.h"
#include "render/trace.h"
#include "scenes/builtin.h"

using namespace trident;

namespace {

const AccelKind kTrees[] = {AccelKind::bvh, AccelKind::kdtree, AccelKind::octree};

/// Closest hit of one ray with the chosen triangle and slab tests.
template <TriangleTest Test, SlabTest Slabs>
Hit closest_hit(const AnyAccel& accel, const Ray& ray) {
    return accel.visit([&](const auto& structure) {
        NoCounters counters;
        return structure.template intersect<Test, Slabs>(ray, counters);
    });
}

/// The faces of a 4 x 4 x 4 block of unit cubes, two triangles per face: node boxes and cells
/// whose planes are the integer planes the rays below run in.
Mesh cube_lattice() {
    Mesh mesh;
    auto quad = [&](Vec3f p, Vec3f du, Vec3f dv) {
        const std::uint32_t a = mesh.add_vertex(p), b = mesh.add_vertex(p + du), c = mesh.add_vertex(p + du + dv),
                            d = mesh.add_vertex(p + dv);
        mesh.add_triangle(a, b, c);
        mesh.add_triangle(a, c, d);
    };
    for (int i = 0; i <= 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 4; ++k) {
                const float a = float(i), b = float(j), c = float(k);
                quad({a, b, c}, {0, 1, 0}, {0, 0, 1});
                quad({b, a, c}, {0, 0, 1}, {1, 0, 0});
                quad({b, c, a}, {1, 0, 0}, {0, 1, 0});
            }
    return mesh;
}

/// Axis-parallel rays (+0 and -0 in the other components) whose origins lie on the integer planes
/// of a second axis, so they run inside shared faces of boxes and cells and hit the lattice on
/// shared edges.
std::vector<Ray> rays_in_shared_faces() {
    std::vector<Ray> rays;
    for (int axis = 0; axis < 3; ++axis)
        for (float sign : {1.0f, -1.0f})
            for (float zero : {0.0f, -0.0f})
                for (int u = 0; u <= 4; ++u)
                    for (int v = 0; v <= 8; ++v) {
                        Ray ray;
                        ray.dir = Vec3f{zero, zero, zero};
                        ray.dir[axis] = sign;
                        ray.origin[axis] = sign > 0 ? -1.0f : 5.0f;
                        ray.origin[(axis + 1) % 3] = float(u);
                        ray.origin[(axis + 2) % 3] = 0.5f * float(v);
                        rays.push_back(ray);
                    }
    return rays;
}

}  // namespace

TEST_CASE("robust and fast slab tests agree on hit or miss for camera rays of the teapot, scalar and packets") {
    const Scene scene = make_builtin_scene("teapot");
    const Camera camera(scene.camera, 96, 54);
    for (AccelKind kind : kTrees) {
        const AnyAccel accel = AnyAccel::build(kind, scene.mesh);
        for (TriangleTest test : {TriangleTest::watertight, TriangleTest::moller_trumbore}) {
            const std::string kind_name = to_string(kind), test_name = to_string(test);
            CAPTURE(kind_name);
            CAPTURE(test_name);
            const std::vector<Hit> robust = trace_primary(accel, camera, test);
            std::size_t hits = 0;
            for (const Hit& h : robust) hits += h.is_hit();
            CHECK(hits > 0);
            for (SimdWidth width : {SimdWidth::scalar, SimdWidth::w8}) {
                if (!is_runnable(width)) continue;
                const std::string width_name = to_string(width);
                CAPTURE(width_name);
                const std::vector<Hit> fast = trace_primary(accel, camera, test, width, SlabTest::fast);
                std::size_t differ = 0;
                for (std::size_t i = 0; i < robust.size(); ++i) differ += robust[i].is_hit() != fast[i].is_hit();
                CHECK(differ == 0);
            }
        }
    }
}

TEST_CASE("the robust slab test never loses a hit on rays running inside shared box faces; the fast one may") {
    const Mesh mesh = cube_lattice();
    const std::vector<Ray> rays = rays_in_shared_faces();
    const AnyAccel brute = AnyAccel::build(AccelKind::brute, mesh);
    std::vector<Hit> reference;
    std::size_t reference_hits = 0;
    for (const Ray& ray : rays) {
        reference.push_back(closest_hit<TriangleTest::watertight, SlabTest::robust>(brute, ray));
        reference_hits += reference.back().is_hit();
    }
    REQUIRE(reference_hits > rays.size() / 2);
    for (AccelKind kind : kTrees) {
        const std::string kind_name = to_string(kind);
        CAPTURE(kind_name);
        const AnyAccel accel = AnyAccel::build(kind, mesh);
        std::size_t robust_lost = 0, robust_wrong_t = 0, fast_lost = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (!reference[i].is_hit()) continue;
            const Hit robust = closest_hit<TriangleTest::watertight, SlabTest::robust>(accel, rays[i]);
            robust_lost += !robust.is_hit();
            robust_wrong_t += robust.is_hit() && robust.t != reference[i].t;
            fast_lost += !closest_hit<TriangleTest::watertight, SlabTest::fast>(accel, rays[i]).is_hit();
        }
        CHECK(robust_lost == 0);
        CHECK(robust_wrong_t == 0);
        MESSAGE(kind_name, ": fast slab test lost ", fast_lost, " of ", reference_hits,
                " hits on rays inside shared faces (robust: ", robust_lost, ")");
    }
}
