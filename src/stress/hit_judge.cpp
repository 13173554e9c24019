#include "stress/hit_judge.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace trident {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = 0x1p-24, kRoundings = 64.0;

/// A ray lying in the plane of a non-degenerate triangle sees it edge-on: in exact arithmetic a
/// watertight test reports no hit (det = 0), but rounding may give one anywhere along the segment
/// the ray shares with the triangle, and such a hit is on the surface. So the fit is "may hit"
/// over that segment [t_in, t_out]: t = t_in, the t tolerance reaching t_out, margin 0 (on the
/// boundary, never a must-hit). A parallel ray off the plane, or one missing the triangle within
/// the plane, cannot hit it.
TriangleFit fit_in_plane(const Vec3d& o, const Vec3d& d, const Vec3d& a, const Vec3d& b, const Vec3d& c,
                         const Vec3d& normal, const Ray& ray, double reach) {
    constexpr TriangleFit kNoHit{kInf, -kInf, 0.0, 0.0};
    const double normal_length = length(normal);
    if (std::abs(dot(o - a, normal)) > kRoundings * kEps * reach * normal_length) return kNoHit;
    // Project on the plane of the two axes other than the normal's largest component, where the
    // triangle keeps a nonzero area, and clip the ray's parameter to each edge's inner side.
    const int drop = largest_abs_axis(normal);
    const int i = (drop + 1) % 3, j = (drop + 2) % 3;
    auto edge = [&](const Vec3d& p, const Vec3d& q, const Vec3d& x) {  // 2D cross of q - p and x - p
        return (q[i] - p[i]) * (x[j] - p[j]) - (q[j] - p[j]) * (x[i] - p[i]);
    };
    const double orientation = edge(a, b, c) > 0.0 ? 1.0 : -1.0;
    const double slack = kRoundings * kEps * reach * reach;  // edge functions are areas
    const Vec3d far_point = o + d;
    double t_in = double(ray.tmin), t_out = double(ray.tmax);
    for (const auto& [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
        const double at_origin = orientation * edge(p, q, o);
        const double rate = orientation * edge(p, q, far_point) - at_origin;  // per unit of t
        if (rate == 0.0) {
            if (at_origin < -slack) return kNoHit;
        } else if (rate > 0.0) {
            t_in = std::max(t_in, (-slack - at_origin) / rate);
        } else {
            t_out = std::min(t_out, (-slack - at_origin) / rate);
        }
    }
    if (!(t_in <= t_out)) return kNoHit;
    const double t_tolerance = (t_out - t_in) + kRoundings * kEps * reach / length(d);
    return {t_in, 0.0, kRoundings * kEps, t_tolerance};
}

}  // namespace

TriangleFit fit_triangle(const Ray& ray, const Triangle& tri) {
    const Vec3d o(ray.origin), d(ray.dir), a(tri.a), b(tri.b), c(tri.c);
    const Vec3d e1 = b - a, e2 = c - a, p = cross(d, e2);
    const double det = dot(e1, p);
    const Vec3d normal = cross(e1, e2);
    if (!(dot(normal, normal) > 0.0)) return {kInf, -kInf, 0.0, 0.0};
    if (det == 0.0) {
        const double reach = std::max({length(a - o), length(b - o), length(c - o)});
        return fit_in_plane(o, d, a, b, c, normal, ray, reach);
    }
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
