#pragma once
// The pinhole camera of ../shared/BENCHMARK.md, evaluated in single precision in the order the
// document writes it, so our primary rays are bit-identical to other tracers following it.
#include <cstdint>

#include "core/lanes.h"
#include "core/ray.h"
#include "core/scene.h"

namespace trident {

class Camera {
public:
    Camera(const CameraSpec& spec, std::uint32_t width, std::uint32_t height);

    /// Primary ray through the centre of pixel (x, y), y = 0 the top row; direction normalized,
    /// tmin = 0, tmax = +inf.
    Ray primary_ray(std::uint32_t x, std::uint32_t y) const {
        return Ray{eye_, primary_direction(float(x), float(y)), 0.0f, kInfinity};
    }

    /// The direction of primary_ray through pixel (x, y), written once over float or an xsimd
    /// batch (one pixel per lane; include simd/lanes.h for batches), so that a packet's rays are
    /// the single rays bit for bit. x and y are pixel numbers, exact as floats.
    template <class T>
    Vec3T<T> primary_direction(const T& x, const T& y) const {
        const Vec3T<T> d = unnormalized_direction(x, y);
        return d / Lanes<T>::sqrt(dot(d, d));  // normalize(d)
    }

    /// The unnormalized direction through pixel (x, y) in double; x and y need not be whole
    /// (x - 0.5 is the pixel's left edge). For bounds on a tile's rays (render/tile_frustum.h),
    /// which normalizing would only scale.
    Vec3d direction_in_double(double x, double y) const { return unnormalized_direction(x, y); }

    std::uint32_t width() const { return width_; }
    std::uint32_t height() const { return height_; }
    const Vec3f& eye() const { return eye_; }
    const Vec3f& forward() const { return forward_; }

private:
    /// forward + sx * right + sy * up of BENCHMARK.md, in T's arithmetic.
    template <class T>
    Vec3T<T> unnormalized_direction(const T& x, const T& y) const {
        const T sx = (T(2.0f) * (x + T(0.5f)) / T(float(width_)) - T(1.0f)) * T(tx_);
        const T sy = (T(1.0f) - T(2.0f) * (y + T(0.5f)) / T(float(height_))) * T(ty_);
        return Vec3T<T>(forward_) + sx * Vec3T<T>(right_) + sy * Vec3T<T>(up_);
    }

    Vec3f eye_, forward_, right_, up_;
    float tx_, ty_;
    std::uint32_t width_, height_;
};

}  // namespace trident
