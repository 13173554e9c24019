#pragma once
// Primary rays of a scene's camera through random pixels, for tests on the built-in scenes: the
// pinhole of ../shared/BENCHMARK.md at 16:9, with a pixel position drawn uniformly in the image.
#include <cmath>
#include <random>
#include <vector>

#include "core/ray.h"
#include "core/scene.h"

namespace trident::testing {

inline std::vector<Ray> camera_rays(const CameraSpec& camera, std::size_t count, std::uint32_t seed) {
    constexpr float kPi = 3.14159265358979f;
    const Vec3f forward = normalize(camera.target - camera.eye);
    const Vec3f right = normalize(cross(forward, camera.up));
    const Vec3f up = cross(right, forward);
    const float ty = std::tan(camera.fov_y_deg * kPi / 360.0f), tx = ty * 16.0f / 9.0f;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    std::vector<Ray> rays(count);
    for (Ray& ray : rays) {
        ray.origin = camera.eye;
        ray.dir = normalize(forward + right * (unit(rng) * tx) + up * (unit(rng) * ty));
    }
    return rays;
}

}  // namespace trident::testing
