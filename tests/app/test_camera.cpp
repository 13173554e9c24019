#include <doctest/doctest.h>

#include "camera/camera.h"

using namespace trident;

TEST_CASE("primary rays follow BENCHMARK.md: a 2x2 image with a 90 degree field of view") {
    const Camera camera(CameraSpec{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90.0f}, 2, 2);
    // Pixel (0, 0): sx = -0.5 * tx, sy = +0.5 * ty with tx = ty = 1; right = +x, up' = +y.
    const Ray top_left = camera.primary_ray(0, 0);
    CHECK(top_left.dir.x == doctest::Approx(-0.408248));
    CHECK(top_left.dir.y == doctest::Approx(0.408248));
    CHECK(top_left.dir.z == doctest::Approx(-0.816497));
    const Ray bottom_right = camera.primary_ray(1, 1);
    CHECK(bottom_right.dir.x == doctest::Approx(0.408248));
    CHECK(bottom_right.dir.y == doctest::Approx(-0.408248));
    CHECK(top_left.tmin == 0.0f);
    CHECK(top_left.tmax == kInfinity);
    CHECK(top_left.origin == Vec3f{0, 0, 0});
}

TEST_CASE("the horizontal extent follows the aspect ratio and the up vector is re-orthogonalized") {
    const Camera camera(CameraSpec{{1, 2, 3}, {1, 2, 2}, {0, 1, 0.5f}, 60.0f}, 1920, 1080);
    const Ray ray = camera.primary_ray(1919, 540);
    const float ty = std::tan(60.0f * 3.14159265f / 360.0f);
    const float tx = ty * 1920.0f / 1080.0f;
    const float sx = (2.0f * 1919.5f / 1920.0f - 1.0f) * tx;
    const float sy = (1.0f - 2.0f * 540.5f / 1080.0f) * ty;
    const Vec3f expected = normalize(Vec3f{0, 0, -1} + Vec3f{sx, 0, 0} + Vec3f{0, sy, 0});
    CHECK(ray.dir.x == doctest::Approx(expected.x));
    CHECK(ray.dir.y == doctest::Approx(expected.y));
    CHECK(ray.dir.z == doctest::Approx(expected.z));
    CHECK(length(ray.dir) == doctest::Approx(1.0f));
}
