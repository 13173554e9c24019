#include "camera/camera.h"

#include <cmath>
#include <numbers>

namespace trident {

Camera::Camera(const CameraSpec& spec, std::uint32_t width, std::uint32_t height)
    : eye_(spec.eye), width_(width), height_(height) {
    forward_ = normalize(spec.target - spec.eye);
    right_ = normalize(cross(forward_, spec.up));
    up_ = cross(right_, forward_);
    ty_ = std::tan(spec.fov_y_deg * std::numbers::pi_v<float> / 360.0f);
    tx_ = ty_ * float(width) / float(height);
}

Ray Camera::primary_ray(std::uint32_t x, std::uint32_t y) const {
    const float sx = (2.0f * (float(x) + 0.5f) / float(width_) - 1.0f) * tx_;
    const float sy = (1.0f - 2.0f * (float(y) + 0.5f) / float(height_)) * ty_;
    return Ray{eye_, normalize(forward_ + sx * right_ + sy * up_), 0.0f, kInfinity};
}

}  // namespace trident
