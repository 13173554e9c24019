#pragma once
// The pinhole camera of ../shared/BENCHMARK.md, evaluated in single precision in the order the
// document writes it, so our primary rays are bit-identical to other tracers following it.
#include <cstdint>

#include "core/ray.h"
#include "core/scene.h"

namespace trident {

class Camera {
public:
    Camera(const CameraSpec& spec, std::uint32_t width, std::uint32_t height);

    /// Primary ray through the centre of pixel (x, y), y = 0 the top row; direction normalized,
    /// tmin = 0, tmax = +inf.
    Ray primary_ray(std::uint32_t x, std::uint32_t y) const;

    std::uint32_t width() const { return width_; }
    std::uint32_t height() const { return height_; }
    const Vec3f& eye() const { return eye_; }
    const Vec3f& forward() const { return forward_; }

private:
    Vec3f eye_, forward_, right_, up_;
    float tx_, ty_;
    std::uint32_t width_, height_;
};

}  // namespace trident
