#pragma once
// Primary rays of a scene's camera for tests on the built-in scenes, from the pinhole of
// ../shared/BENCHMARK.md: through random points of a 16:9 image, or through pixel blocks as the
// renderer's packets take them.
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

/// Primary rays of `blocks` pixel blocks, `block_w` x `block_h` pixels each, of a `width` x
/// `height` image, computed as ../shared/BENCHMARK.md writes them; a block's rays are
/// consecutive, row by row. The first block sits at the image centre, where packets straddle the
/// view axis; the others at random.
inline std::vector<Ray> pixel_block_rays(const CameraSpec& camera, int width, int height, int block_w, int block_h,
                                         std::size_t blocks, std::uint32_t seed) {
    constexpr float kPi = 3.14159265358979f;
    const Vec3f forward = normalize(camera.target - camera.eye);
    const Vec3f right = normalize(cross(forward, camera.up));
    const Vec3f up = cross(right, forward);
    const float ty = std::tan(camera.fov_y_deg * kPi / 360.0f), tx = ty * float(width) / float(height);
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> column(0, width - block_w), row(0, height - block_h);
    std::vector<Ray> rays;
    for (std::size_t b = 0; b < blocks; ++b) {
        const int x0 = b == 0 ? (width - block_w) / 2 : column(rng), y0 = b == 0 ? (height - block_h) / 2 : row(rng);
        for (int y = y0; y < y0 + block_h; ++y)
            for (int x = x0; x < x0 + block_w; ++x) {
                const float sx = (2.0f * (float(x) + 0.5f) / float(width) - 1.0f) * tx;
                const float sy = (1.0f - 2.0f * (float(y) + 0.5f) / float(height)) * ty;
                rays.push_back({camera.eye, normalize(forward + sx * right + sy * up)});
            }
    }
    return rays;
}

}  // namespace trident::testing
