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

}  // namespace trident
