#include <doctest/doctest.h>

#include <cstring>
#include <random>
#include <vector>

#include "accel/any_accel.h"
#include "core/slab_test.h"
#include "render/tile_frustum.h"
#include "render/trace.h"
#include "render_test_scenes.h"
#include "support/random_scenes.h"

using namespace trident;

namespace {

/// Whether the tile's rays, as traced (float, robust slab test), enter the box.
bool some_ray_enters(const Camera& camera, const ImageTile& tile, const Vec3f& lo, const Vec3f& hi) {
    for (std::uint32_t y = tile.y0; y != tile.y1; ++y)
        for (std::uint32_t x = tile.x0; x != tile.x1; ++x) {
            const Ray ray = camera.primary_ray(x, y);
            float t_entry;
            if (intersect_slabs(SlabRay(ray.origin, ray.dir), lo, hi, ray.tmin, ray.tmax, t_entry)) return true;
        }
    return false;
}

/// A random camera over the box [-1, 1]^3 of an image with partial tiles at its right and bottom.
Camera random_camera(std::mt19937& rng) {
    std::uniform_real_distribution<float> coordinate(-3.0f, 3.0f), fov(20.0f, 100.0f);
    CameraSpec spec;
    spec.eye = {coordinate(rng), coordinate(rng), 4.0f + coordinate(rng)};
    spec.target = {0.3f * coordinate(rng), 0.3f * coordinate(rng), 0.3f * coordinate(rng)};
    spec.fov_y_deg = fov(rng);
    std::uniform_int_distribution<std::uint32_t> size(17, 70);
    return Camera(spec, size(rng), size(rng));
}

/// A structure known only by its box, as TileCuller reads a KD-tree's.
struct OneBox {
    Aabb box;
    const Aabb& bounds() const { return box; }
};

bool may_hit(const Camera& camera, const ImageTile& tile, const Vec3f& lo, const Vec3f& hi) {
    return TileCuller(OneBox{{lo, hi}}, camera).may_hit(tile);
}

bool same_hits(const std::vector<Hit>& a, const std::vector<Hit>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].triangle != b[i].triangle || std::memcmp(&a[i].t, &b[i].t, sizeof(float)) != 0 ||
            std::memcmp(&a[i].u, &b[i].u, sizeof(float)) != 0 || std::memcmp(&a[i].v, &b[i].v, sizeof(float)) != 0)
            return false;
    return true;
}

}  // namespace

TEST_CASE("a tile is culled only where none of its traced rays enters the box") {
    std::mt19937 rng(20261207);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), far(0.5f, 12.0f), size(0.0f, 0.02f);
    std::size_t dropped = 0, kept_but_missed = 0, wrongly_dropped = 0;
    for (int scene = 0; scene < 30; ++scene) {
        const Camera camera = random_camera(rng);
        for (std::size_t index = 0; index < tile_count(camera); ++index) {
            const ImageTile tile = tile_at(camera, index);
            for (int b = 0; b < 40; ++b) {
                // Small boxes about points on rays through pixels near the tile's edges, inside and
                // just outside it: the boxes the test must keep are the ones it comes closest to
                // dropping. Some are flat, as a wall's box is.
                const std::uint32_t x = tile.x0 + std::uint32_t(unit(rng) * float(tile.x1 - tile.x0 + 2)) - 1;
                const std::uint32_t y = tile.y0 + std::uint32_t(unit(rng) * float(tile.y1 - tile.y0 + 2)) - 1;
                const Ray ray = camera.primary_ray(std::min(x, camera.width() - 1), std::min(y, camera.height() - 1));
                const Vec3f centre = ray.origin + far(rng) * ray.dir;
                Vec3f half(size(rng), size(rng), b % 4 == 0 ? 0.0f : size(rng));
                const Vec3f lo = centre - half, hi = centre + half;
                const bool enters = some_ray_enters(camera, tile, lo, hi);
                if (!may_hit(camera, tile, lo, hi)) {
                    ++dropped;
                    wrongly_dropped += enters;
                } else {
                    kept_but_missed += !enters;
                }
            }
        }
    }
    CHECK(wrongly_dropped == 0);
    // Not vacuous: boxes beside the tile are dropped, and only a thin margin is kept in doubt.
    CHECK(dropped > 1000);
    CHECK(kept_but_missed < dropped / 4);
}

TEST_CASE("a tile's frustum: boxes around the eye, across the view, beside the tile, and a tile one pixel wide") {
    const CameraSpec spec{{0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 60.0f};
    const Camera camera(spec, 64, 48);
    const ImageTile top_left = tile_at(camera, 0);
    CHECK(may_hit(camera, top_left, {-1.0f, -1.0f, 4.0f}, {1.0f, 1.0f, 6.0f}));           // holding the eye
    CHECK(may_hit(camera, top_left, {-100.0f, -100.0f, -1.0f}, {100.0f, 100.0f, 0.0f}));  // a wall across the view
    CHECK_FALSE(may_hit(camera, top_left, {0.5f, -0.5f, -1.0f}, {1.0f, 0.0f, 0.0f}));     // bottom right, off the tile
    // An empty structure is hit by no tile; one without bounds may be hit by every tile.
    CHECK_FALSE(TileCuller(OneBox{}, camera).may_hit(top_left));
    struct Unbounded {};
    CHECK(TileCuller(Unbounded{}, camera).may_hit(top_left));
    // The image's last column, one pixel wide: its pyramid is as wide as the pixel.
    const Camera narrow(spec, 17, 17);
    const ImageTile column = tile_at(narrow, 1);
    REQUIRE(column.x1 - column.x0 == 1);
    const auto box_on_ray = [&](std::uint32_t x, std::uint32_t y) {
        const Ray ray = narrow.primary_ray(x, y);
        const Vec3f centre = ray.origin + 3.0f * ray.dir;
        return std::pair{centre - Vec3f(1e-3f), centre + Vec3f(1e-3f)};
    };
    const auto [on_lo, on_hi] = box_on_ray(16, 8);
    CHECK(may_hit(narrow, column, on_lo, on_hi));
    const auto [off_lo, off_hi] = box_on_ray(8, 8);
    CHECK_FALSE(may_hit(narrow, column, off_lo, off_hi));
}

TEST_CASE("tracing with tile culling gives every structure's and width's hits of tracing every ray") {
    // A soup in one corner of the view, so that most tiles see nothing, from an image whose
    // right and bottom tiles are partial.
    Mesh mesh = testing::random_soup(400, 7);
    testing::add_floor_quad(mesh, 0.5f, 3.0f, -3.0f, -0.5f, -1.5f);
    const Camera camera(CameraSpec{{-2.0f, 1.5f, 6.0f}, {1.5f, -0.5f, 0.0f}, {0.0f, 1.0f, 0.0f}, 70.0f}, 150, 93);
    for (const AccelKind kind : {AccelKind::bvh, AccelKind::bvh2, AccelKind::kdtree, AccelKind::octree}) {
        const AnyAccel accel = AnyAccel::build(kind, mesh);
        std::size_t culled = 0;
        accel.visit([&](const auto& structure) {
            const TileCuller culler(structure, camera);
            for (std::size_t i = 0; i < tile_count(camera); ++i) culled += !culler.may_hit(tile_at(camera, i));
        });
        CAPTURE(int(kind));
        CHECK(culled > 0);
        CHECK(culled < tile_count(camera));
        for (const SimdWidth width : testing::runnable_widths()) {
            CAPTURE(int(width));
            const std::vector<Hit> every_ray =
                trace_primary(accel, camera, TriangleTest::watertight, width, SlabTest::robust, TileCulling::off);
            const std::vector<Hit> culling =
                trace_primary(accel, camera, TriangleTest::watertight, width, SlabTest::robust, TileCulling::frustum);
            CHECK(same_hits(every_ray, culling));
        }
    }
}
