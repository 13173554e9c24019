#pragma once
// Ray/triangle tests. The watertight test of Woop, Benthin and Wald (JCGT 2(1), 2013) is the
// default: it shears the ray to +z once per ray, so edges shared by two triangles are evaluated
// from the same operands and no ray slips between them; edge functions that round to exactly zero
// are recomputed in double (section 4 of the paper). Möller–Trumbore (1997) is the faster,
// non-watertight alternative kept for the speed-against-error comparison. Neither culls back faces.
// A hit counts when ray.tmin <= t < t_limit.
#include <cmath>
#include <utility>

#include "core/mesh.h"
#include "core/ray.h"

namespace trident {

enum class TriangleTest { watertight, moller_trumbore };

inline const char* to_string(TriangleTest test) {
    return test == TriangleTest::watertight ? "watertight" : "moller_trumbore";
}

struct TriangleHit {
    float t, u, v;  // u weighs corner b, v weighs corner c
};

template <TriangleTest Test>
class TriangleIntersector;

template <>
class TriangleIntersector<TriangleTest::watertight> {
public:
    explicit TriangleIntersector(const Ray& ray) : origin_(ray.origin), tmin_(ray.tmin) {
        kz_ = largest_abs_axis(ray.dir);
        kx_ = kz_ == 2 ? 0 : kz_ + 1;
        ky_ = kx_ == 2 ? 0 : kx_ + 1;
        if (ray.dir[kz_] < 0.0f) std::swap(kx_, ky_);  // keep the winding so U, V, W keep their signs
        sx_ = ray.dir[kx_] / ray.dir[kz_];
        sy_ = ray.dir[ky_] / ray.dir[kz_];
        sz_ = 1.0f / ray.dir[kz_];
    }

    bool intersect(const Triangle& tri, float t_limit, TriangleHit& out) const {
        const Vec3f a = tri.a - origin_, b = tri.b - origin_, c = tri.c - origin_;
        const float ax = a[kx_] - sx_ * a[kz_], ay = a[ky_] - sy_ * a[kz_];
        const float bx = b[kx_] - sx_ * b[kz_], by = b[ky_] - sy_ * b[kz_];
        const float cx = c[kx_] - sx_ * c[kz_], cy = c[ky_] - sy_ * c[kz_];
        float u = cx * by - cy * bx;
        float v = ax * cy - ay * cx;
        float w = bx * ay - by * ax;
        if (u == 0.0f || v == 0.0f || w == 0.0f) {
            u = float(double(cx) * double(by) - double(cy) * double(bx));
            v = float(double(ax) * double(cy) - double(ay) * double(cx));
            w = float(double(bx) * double(ay) - double(by) * double(ax));
        }
        if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
        const float det = u + v + w;
        if (det == 0.0f) return false;  // degenerate triangle or ray in its plane
        const float az = sz_ * a[kz_], bz = sz_ * b[kz_], cz = sz_ * c[kz_];
        const float t_scaled = u * az + v * bz + w * cz;
        // Compare t against its limits before dividing; the sign of det orients the inequality.
        const float abs_det = std::abs(det);
        const float signed_t = det < 0.0f ? -t_scaled : t_scaled;
        if (!(signed_t >= tmin_ * abs_det)) return false;
        const float inv_det = 1.0f / det;
        const float t = t_scaled * inv_det;
        if (!(t >= tmin_ && t < t_limit)) return false;
        out = {t, v * inv_det, w * inv_det};
        return true;
    }

private:
    Vec3f origin_;
    float tmin_;
    int kx_, ky_, kz_;
    float sx_, sy_, sz_;
};

template <>
class TriangleIntersector<TriangleTest::moller_trumbore> {
public:
    explicit TriangleIntersector(const Ray& ray) : origin_(ray.origin), dir_(ray.dir), tmin_(ray.tmin) {}

    bool intersect(const Triangle& tri, float t_limit, TriangleHit& out) const {
        const Vec3f e1 = tri.b - tri.a, e2 = tri.c - tri.a;
        const Vec3f p = cross(dir_, e2);
        const float det = dot(e1, p);
        if (det == 0.0f) return false;
        const float inv_det = 1.0f / det;
        const Vec3f s = origin_ - tri.a;
        const float u = dot(s, p) * inv_det;
        if (u < 0.0f || u > 1.0f) return false;
        const Vec3f q = cross(s, e1);
        const float v = dot(dir_, q) * inv_det;
        if (v < 0.0f || u + v > 1.0f) return false;
        const float t = dot(e2, q) * inv_det;
        if (!(t >= tmin_ && t < t_limit)) return false;
        out = {t, u, v};
        return true;
    }

private:
    Vec3f origin_, dir_;
    float tmin_;
};

}  // namespace trident
