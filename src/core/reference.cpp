#include "core/reference.h"

#include <cmath>
#include <utility>

namespace trident {

double intersect_reference(const Ray& ray, const Triangle& tri) {
    constexpr double kMiss = std::numeric_limits<double>::infinity();
    const Vec3d org(ray.origin), dir(ray.dir);
    const int kz = largest_abs_axis(dir);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (dir[kz] < 0.0) std::swap(kx, ky);
    const double sx = dir[kx] / dir[kz], sy = dir[ky] / dir[kz], sz = 1.0 / dir[kz];
    const Vec3d a = Vec3d(tri.a) - org, b = Vec3d(tri.b) - org, c = Vec3d(tri.c) - org;
    const double ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
    const double bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
    const double cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];
    const double u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
    if ((u < 0 || v < 0 || w < 0) && (u > 0 || v > 0 || w > 0)) return kMiss;
    const double det = u + v + w;
    if (det == 0.0) return kMiss;
    const double t = (u * sz * a[kz] + v * sz * b[kz] + w * sz * c[kz]) / det;
    return (t >= ray.tmin && t < ray.tmax) ? t : kMiss;
}

ReferenceHit trace_reference(std::span<const Triangle> triangles, const Ray& ray) {
    ReferenceHit best;
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        const double t = intersect_reference(ray, triangles[i]);
        if (t < best.t) best = {static_cast<TriangleId>(i), t};
    }
    return best;
}

bool occluded_reference(std::span<const Triangle> triangles, const Ray& ray) {
    for (const Triangle& tri : triangles)
        if (std::isfinite(intersect_reference(ray, tri))) return true;
    return false;
}

}  // namespace trident
