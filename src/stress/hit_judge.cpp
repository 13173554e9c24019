#include "stress/hit_judge.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace trident {

TriangleFit fit_triangle(const Ray& ray, const Triangle& tri) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    constexpr double kEps = 0x1p-24, kRoundings = 64.0;
    const Vec3d o(ray.origin), d(ray.dir), a(tri.a), b(tri.b), c(tri.c);
    const Vec3d e1 = b - a, e2 = c - a, p = cross(d, e2);
    const double det = dot(e1, p);
    if (det == 0.0 || !(dot(cross(e1, e2), cross(e1, e2)) > 0.0)) return {kInf, -kInf, 0.0, 0.0};
    const Vec3d s = o - a, q = cross(s, e1);
    const double u = dot(s, p) / det, v = dot(d, q) / det, t = dot(e2, q) / det;
    const double dir_length = length(d);
    const double reach = std::max({length(a - o), length(b - o), length(c - o)});
    const double margin_tolerance = kRoundings * kEps * (1.0 + reach * reach * dir_length / std::abs(det));
    const double t_tolerance = (kRoundings * kEps + 2.0 * margin_tolerance) * reach / dir_length;
    return {t, std::min({u, v, 1.0 - u - v}), margin_tolerance, t_tolerance};
}

bool some_triangle_must_hit(std::span<const Triangle> triangles, const Ray& ray) {
    return std::any_of(triangles.begin(), triangles.end(),
                       [&](const Triangle& tri) { return fit_triangle(ray, tri).must_hit(ray); });
}

bool some_triangle_may_hit(std::span<const Triangle> triangles, const Ray& ray) {
    return std::any_of(triangles.begin(), triangles.end(),
                       [&](const Triangle& tri) { return fit_triangle(ray, tri).may_hit(ray); });
}

}  // namespace trident
