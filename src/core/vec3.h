#pragma once
// A 3-vector over any arithmetic value type: float for single rays, double for the reference
// tracer, and (later) an xsimd batch for ray packets, so one formula serves all three.
#include <cmath>
#include <cstddef>

namespace trident {

template <class T>
struct Vec3T {
    T x{}, y{}, z{};

    constexpr Vec3T() = default;
    constexpr Vec3T(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
    constexpr explicit Vec3T(T s) : x(s), y(s), z(s) {}
    template <class U>
    constexpr explicit Vec3T(const Vec3T<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}

    constexpr T& operator[](int axis) { return axis == 0 ? x : (axis == 1 ? y : z); }
    constexpr const T& operator[](int axis) const { return axis == 0 ? x : (axis == 1 ? y : z); }
};

using Vec3f = Vec3T<float>;
using Vec3d = Vec3T<double>;

template <class T> constexpr Vec3T<T> operator+(const Vec3T<T>& a, const Vec3T<T>& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class T> constexpr Vec3T<T> operator-(const Vec3T<T>& a, const Vec3T<T>& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class T> constexpr Vec3T<T> operator-(const Vec3T<T>& a) { return {-a.x, -a.y, -a.z}; }
template <class T> constexpr Vec3T<T> operator*(const Vec3T<T>& a, const Vec3T<T>& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
template <class T> constexpr Vec3T<T> operator*(const Vec3T<T>& a, T s) { return {a.x * s, a.y * s, a.z * s}; }
template <class T> constexpr Vec3T<T> operator*(T s, const Vec3T<T>& a) { return {a.x * s, a.y * s, a.z * s}; }
template <class T> constexpr Vec3T<T> operator/(const Vec3T<T>& a, T s) { return {a.x / s, a.y / s, a.z / s}; }
template <class T> constexpr Vec3T<T>& operator+=(Vec3T<T>& a, const Vec3T<T>& b) { return a = a + b; }
template <class T> constexpr bool operator==(const Vec3T<T>& a, const Vec3T<T>& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

template <class T> constexpr T dot(const Vec3T<T>& a, const Vec3T<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class T> constexpr Vec3T<T> cross(const Vec3T<T>& a, const Vec3T<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T> inline T length(const Vec3T<T>& a) { return std::sqrt(dot(a, a)); }
template <class T> inline Vec3T<T> normalize(const Vec3T<T>& a) { return a / length(a); }

template <class T> constexpr Vec3T<T> min(const Vec3T<T>& a, const Vec3T<T>& b) {
    return {a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z};
}
template <class T> constexpr Vec3T<T> max(const Vec3T<T>& a, const Vec3T<T>& b) {
    return {a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z};
}
template <class T> inline bool is_finite(const Vec3T<T>& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

/// Index of the component with the largest absolute value (ties go to the lower axis).
template <class T> inline int largest_abs_axis(const Vec3T<T>& a) {
    const T ax = std::abs(a.x), ay = std::abs(a.y), az = std::abs(a.z);
    return ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
}

}  // namespace trident
