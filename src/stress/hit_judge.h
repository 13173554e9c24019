#pragma once
// How far a float hit may stray from the double-precision reference before it counts as wrong.
//
// Each triangle is re-evaluated in double (Möller–Trumbore): the plane distance t and the
// barycentric margin, min(u, v, 1 - u - v), which is negative outside the triangle. A float
// watertight test computes its edge functions from corners translated to the ray origin, so its
// errors scale with the corners' distance L from the origin; normalised by the triangle's area
// projected across the ray (|det| / |d|), the margin is off by at most
//     margin_tolerance = K eps (1 + L^2 |d| / |det|),
// and t, a barycentric blend of the corners' distances, by at most
//     t_tolerance = (K eps + 2 margin_tolerance) L / |d|,
// with eps = 2^-24 and K = 64 (a few roundings per operation, with room). A hit within these of
// the reference is agreement; a disagreement is counted only beyond them. Zero-area triangles
// have no margin (-inf): hitting one is always wrong. A ray lying in a triangle's plane (det = 0)
// sees it edge-on: it may hit it, never must, anywhere along the segment they share.
#include <limits>
#include <span>

#include "core/mesh.h"
#include "core/ray.h"

namespace trident {

struct TriangleFit {
    double t;                 // where the ray meets the triangle's plane (inf when it cannot: degenerate,
                              // or parallel off the plane; the first shared point when in the plane)
    double margin;            // min barycentric coordinate there (-inf when it cannot meet it; 0 in the plane)
    double margin_tolerance;  // the float test's error bound on margin
    double t_tolerance;       // ... and on t

    bool degenerate() const { return margin == -std::numeric_limits<double>::infinity(); }
    /// The float test may hit it: within the tolerance of the triangle, and of the ray's range.
    bool may_hit(const Ray& ray) const {
        return margin >= -margin_tolerance && t >= double(ray.tmin) - t_tolerance && t < double(ray.tmax) + t_tolerance;
    }
    /// The float test must hit it: inside by more than the tolerance, and inside the ray's range.
    bool must_hit(const Ray& ray) const {
        return margin > margin_tolerance && t >= double(ray.tmin) + t_tolerance && t < double(ray.tmax) - t_tolerance;
    }
};

TriangleFit fit_triangle(const Ray& ray, const Triangle& tri);

/// Whether some triangle must be hit by any correct float test (the reference's hit is not a
/// near-edge case); the O(N) scan is only made for disagreements.
bool some_triangle_must_hit(std::span<const Triangle> triangles, const Ray& ray);
/// Whether some triangle may be hit (a float occlusion answer of "yes" can be right).
bool some_triangle_may_hit(std::span<const Triangle> triangles, const Ray& ray);

}  // namespace trident
