#pragma once
// Ray/triangle tests. The watertight test of Woop, Benthin and Wald (JCGT 2(1), 2013) is the
// default: it shears the ray to +z once per ray, so edges shared by two triangles are evaluated
// from the same operands and no ray slips between them; edge functions that round to exactly zero
// are recomputed in double (section 4 of the paper). Möller–Trumbore (1997) is the faster,
// non-watertight alternative kept for the speed-against-error comparison. Neither culls back faces.
// A hit counts when ray.tmin <= t < t_limit; the watertight test decides a t within its rounding
// of 0 again in double, so a ray leaving a surface does not hit the surface's coplanar neighbours.
//
// Each test is written once over a value type T: float for one ray (TriangleIntersector<Test>),
// an xsimd batch for a packet with one ray per lane (simd/lanes.h supplies Lanes<batch>). A lane
// of a packet gives the same hit, t, u and v bits as the scalar test on that lane's ray.
#include <array>
#include <bit>
#include <cassert>
#include <concepts>
#include <cstdint>
#include <optional>
#include <string_view>

#include "core/lanes.h"
#include "core/mesh.h"
#include "core/ray.h"
#include "core/rounding.h"

namespace trident {

enum class TriangleTest { watertight, moller_trumbore };

inline const char* to_string(TriangleTest test) {
    return test == TriangleTest::watertight ? "watertight" : "moller_trumbore";
}

/// Reads what to_string() writes, and "mt" for Möller–Trumbore.
inline std::optional<TriangleTest> parse_triangle_test(std::string_view name) {
    if (name == "watertight") return TriangleTest::watertight;
    if (name == "moller_trumbore" || name == "mt") return TriangleTest::moller_trumbore;
    return std::nullopt;
}

template <class T>
struct TriangleHitT {
    T t, u, v;  // u weighs corner b, v weighs corner c
};
using TriangleHit = TriangleHitT<float>;

/// Who keeps a zero-area triangle (collinear or repeated corners) from being hit, which rounding
/// could otherwise let through: the test, lane by lane, for each lane that passed every other
/// test (detail::drop_zero_area), or the caller, whose structure left such triangles out when it
/// was built (has_area). Either way they are never hit, so the answers are the same bits.
enum class ZeroAreaTriangles { dropped_by_test, left_out_by_caller };

/// Twice the triangle's area vector in double: zero exactly when the corners are collinear, since
/// differences of floats and their products are exact in double (for corners whose exponents
/// differ by less than 29).
inline Vec3d area_vector_in_double(const Vec3d& a, const Vec3d& b, const Vec3d& c) { return cross(b - a, c - a); }

/// Whether the triangle tests can hit `tri` at all: false for a zero-area triangle.
inline bool has_area(const Triangle& tri) {
    return !(area_vector_in_double(Vec3d(tri.a), Vec3d(tri.b), Vec3d(tri.c)) == Vec3d(0.0));
}

/// Constructed once per ray (or packet); intersect() returns the lanes that hit and writes their
/// t, u, v to `out`. Lanes that miss leave unspecified values in `out` (a scalar miss leaves it
/// untouched).
template <TriangleTest Test, class T>
class TriangleIntersectorT;

/// The single-ray tests the structures use.
template <TriangleTest Test>
using TriangleIntersector = TriangleIntersectorT<Test, float>;

namespace detail {

/// Section 4 of Woop et al.: where an edge function rounds to exactly zero, all three are
/// recomputed in double. Products of floats are exact in double, so the result does not depend
/// on whether the compiler fuses the multiply and the subtraction. Rare, so done lane by lane.
template <class T>
void edge_functions_in_double(typename Lanes<T>::Mask lanes, const T& ax, const T& ay, const T& bx, const T& by,
                              const T& cx, const T& cy, T& u, T& v, T& w) {
    using L = Lanes<T>;
    const auto ax_ = L::to_array(ax), ay_ = L::to_array(ay), bx_ = L::to_array(bx);
    const auto by_ = L::to_array(by), cx_ = L::to_array(cx), cy_ = L::to_array(cy);
    auto u_ = L::to_array(u), v_ = L::to_array(v), w_ = L::to_array(w);
    for (std::uint32_t bits = L::bits(lanes); bits != 0; bits &= bits - 1) {
        const int i = std::countr_zero(bits);
        u_[i] = float(double(cx_[i]) * double(by_[i]) - double(cy_[i]) * double(bx_[i]));
        v_[i] = float(double(ax_[i]) * double(cy_[i]) - double(ay_[i]) * double(cx_[i]));
        w_[i] = float(double(bx_[i]) * double(ay_[i]) - double(by_[i]) * double(ax_[i]));
    }
    u = L::from_array(u_);
    v = L::from_array(v_);
    w = L::from_array(w_);
}

/// A vector's lanes in memory, for the rare fallbacks done lane by lane in double.
template <class T>
class LanesInDouble {
public:
    explicit LanesInDouble(const Vec3T<T>& v)
        : x_(Lanes<T>::to_array(v.x)), y_(Lanes<T>::to_array(v.y)), z_(Lanes<T>::to_array(v.z)) {}
    Vec3d operator[](int lane) const { return Vec3d(x_[lane], y_[lane], z_[lane]); }

private:
    typename Lanes<T>::Array x_, y_, z_;
};

/// `mask` without the lanes whose bit is set in `dropped`.
template <class T>
typename Lanes<T>::Mask without_lanes(typename Lanes<T>::Mask mask, std::uint32_t dropped) {
    using L = Lanes<T>;
    if (dropped == 0) return mask;
    typename L::Array keep{};
    for (std::size_t i = 0; i < L::width; ++i) keep[i] = (dropped >> i) & 1u ? 0.0f : 1.0f;
    return mask & (L::from_array(keep) != T(0.0f));
}

/// The hit lanes whose triangle has area. A zero-area triangle (collinear or repeated corners)
/// has det = 0 in exact arithmetic, but its corners, translated and sheared in float, need not
/// stay collinear, so det may round away from zero and a ray passing its segment would hit it;
/// area_vector_in_double tells exactly. Only lanes that passed every other test get here; done
/// lane by lane, and kept out of line so that it does not bloat the triangle loops it is called
/// from. A packet's lanes that all hit one triangle repeat the same test: a structure that leaves
/// zero-area triangles out at build time skips it (ZeroAreaTriangles).
template <class T>
[[gnu::noinline]] typename Lanes<T>::Mask drop_zero_area(typename Lanes<T>::Mask hit, const Vec3T<T>& a, const Vec3T<T>& b,
                                       const Vec3T<T>& c) {
    const LanesInDouble<T> a_(a), b_(b), c_(c);
    std::uint32_t zero_area = 0;
    for (std::uint32_t bits = Lanes<T>::bits(hit); bits != 0; bits &= bits - 1) {
        const int i = std::countr_zero(bits);
        if (area_vector_in_double(a_[i], b_[i], c_[i]) == Vec3d(0.0)) zero_area |= 1u << i;
    }
    return without_lanes<T>(hit, zero_area);
}

/// Of the `near_origin` lanes, those whose plane the ray really crosses before tmin, dropped from
/// `hit`: the plane crossing recomputed in double from the unrounded corners, origin and
/// direction (differences of floats are exact in double, and what follows rounds at 2^-53, so
/// the sign comes out right unless the origin lies within about 2^-50 of the corners' scale from
/// the plane, far inside any offset). Lane by lane and out of line, as it is rare: a hit gets
/// here only when its t lies within rounding of the origin.
template <class T>
[[gnu::noinline]] typename Lanes<T>::Mask drop_crossings_before_tmin(typename Lanes<T>::Mask hit,
                                                                     typename Lanes<T>::Mask near_origin,
                                                                     const Vec3T<T>& a, const Vec3T<T>& b,
                                                                     const Vec3T<T>& c, const Vec3T<T>& origin,
                                                                     const Vec3T<T>& dir, const T& tmin) {
    const LanesInDouble<T> a_(a), b_(b), c_(c), origin_(origin), dir_(dir);
    const auto tmin_ = Lanes<T>::to_array(tmin);
    std::uint32_t before = 0;
    for (std::uint32_t bits = Lanes<T>::bits(hit & near_origin); bits != 0; bits &= bits - 1) {
        const int i = std::countr_zero(bits);
        const Vec3d normal = cross(b_[i] - a_[i], c_[i] - a_[i]);
        const double t = dot(normal, a_[i] - origin_[i]) / dot(normal, dir_[i]);
        if (!(t >= double(tmin_[i]))) before |= 1u << i;
    }
    return without_lanes<T>(hit, before);
}

}  // namespace detail

template <class T>
class TriangleIntersectorT<TriangleTest::watertight, T> {
    using L = Lanes<T>;

public:
    using Mask = typename L::Mask;

    TriangleIntersectorT(const Vec3T<T>& origin, const Vec3T<T>& dir, T tmin)
        : origin_(origin),
          dir_(dir),
          tmin_(tmin),
          axes_(L::major_axis_to_z(dir)),
          origin_in_ray_axes_(axes_.apply(origin)) {
        const Vec3T<T> d = axes_.apply(dir);
        sx_ = d.x / d.z;
        sy_ = d.y / d.z;
        sz_ = T(1.0f) / d.z;
    }
    explicit TriangleIntersectorT(const Ray& ray) requires std::same_as<T, float>
        : TriangleIntersectorT(ray.origin, ray.dir, ray.tmin) {}
    /// Every lane set up for one ray: its scalar set-up broadcast, for one ray against a batch of
    /// triangles. The same bits as the set-up over broadcast vectors (each value is the same
    /// operation on the same operands), without its lane-wise selects and lane-indexed loads.
    explicit TriangleIntersectorT(const TriangleIntersectorT<TriangleTest::watertight, float>& one_ray)
        requires(!std::same_as<T, float>)
        : origin_(one_ray.origin_),
          dir_(one_ray.dir_),
          tmin_(one_ray.tmin_),
          axes_(L::broadcast(one_ray.axes_)),
          origin_in_ray_axes_(one_ray.origin_in_ray_axes_),
          sx_(one_ray.sx_),
          sy_(one_ray.sy_),
          sz_(one_ray.sz_) {}

    Mask intersect(const Triangle& tri, T t_limit, TriangleHitT<T>& out) const {
        return intersect(Vec3T<T>(tri.a), Vec3T<T>(tri.b), Vec3T<T>(tri.c), t_limit, out);
    }

    template <ZeroAreaTriangles ZeroArea = ZeroAreaTriangles::dropped_by_test>
    Mask intersect(const Vec3T<T>& tri_a, const Vec3T<T>& tri_b, const Vec3T<T>& tri_c, T t_limit,
                   TriangleHitT<T>& out) const {
        return sheared<ZeroArea>(axes_.apply(tri_a - origin_), axes_.apply(tri_b - origin_),
                                 axes_.apply(tri_c - origin_), t_limit, out,
                                 [&] { return std::array{tri_a, tri_b, tri_c}; });
    }

    /// Which of the world's axes become the test's x, y and z (z: the direction's largest); one
    /// permutation for every lane, which holds where all lanes trace one ray.
    std::array<int, 3> ray_axes() const {
        assert(uniform_axes());
        return {axes_.kx, axes_.ky, axes_.kz};
    }

    /// The same test for corners given in the ray's axes (component i of each is the world's
    /// ray_axes()[i]): triangles stored by coordinate are loaded so as they stand, where the
    /// permutation would otherwise pick components triangle by triangle. Differences and
    /// permutations commute exactly, so the hits are the same bits as intersect()'s.
    /// `world_corners()` returns the corners in the world's axes (a std::array of three) for the
    /// rare checks in double; a caller that holds the triangles in memory reads them again there
    /// (capturing these corners instead kept them in memory on every test: 4-11% slower).
    template <ZeroAreaTriangles ZeroArea = ZeroAreaTriangles::dropped_by_test, class WorldCorners>
    Mask intersect_in_ray_axes(const Vec3T<T>& a, const Vec3T<T>& b, const Vec3T<T>& c, T t_limit, TriangleHitT<T>& out,
                               const WorldCorners& world_corners) const {
        assert(uniform_axes());
        return sheared<ZeroArea>(a - origin_in_ray_axes_, b - origin_in_ray_axes_, c - origin_in_ray_axes_, t_limit,
                                 out, world_corners);
    }

private:
    template <TriangleTest, class>
    friend class TriangleIntersectorT;  // the scalar set-up read by the broadcasting constructor

    bool uniform_axes() const {
        if constexpr (std::same_as<T, float>)
            return true;
        else
            return axes_.uniform;
    }

    /// The test on the corners moved to the ray's origin and permuted to its axes; `world_corners`
    /// gives them as the caller has them, for the rare checks in double.
    template <ZeroAreaTriangles ZeroArea, class WorldCorners>
    Mask sheared(const Vec3T<T>& a, const Vec3T<T>& b, const Vec3T<T>& c, T t_limit, TriangleHitT<T>& out,
                 const WorldCorners& world_corners) const {
        const T zero(0.0f);
        const T ax = a.x - sx_ * a.z, ay = a.y - sy_ * a.z;
        const T bx = b.x - sx_ * b.z, by = b.y - sy_ * b.z;
        const T cx = c.x - sx_ * c.z, cy = c.y - sy_ * c.z;
        T u = cx * by - cy * bx;
        T v = ax * cy - ay * cx;
        T w = bx * ay - by * ax;
        const Mask on_edge = (u == zero) | (v == zero) | (w == zero);
        if (L::any(on_edge)) detail::edge_functions_in_double(on_edge, ax, ay, bx, by, cx, cy, u, v, w);
        Mask hit = !(((u < zero) | (v < zero) | (w < zero)) & ((u > zero) | (v > zero) | (w > zero)));
        if (L::none(hit)) return hit;
        const T det = u + v + w;
        hit = hit & (det != zero);  // zero: degenerate triangle or ray in its plane
        if (L::none(hit)) return hit;
        const T az = sz_ * a.z, bz = sz_ * b.z, cz = sz_ * c.z;
        const T t_scaled = u * az + v * bz + w * cz;
        // Compare t against its limits before dividing; the sign of det orients the inequality.
        const T abs_det = L::abs(det);
        const T signed_t = L::select(det < zero, -t_scaled, t_scaled);
        hit = hit & (signed_t >= tmin_ * abs_det);
        if (L::none(hit)) return hit;
        const T inv_det = T(1.0f) / det;
        const T t = t_scaled * inv_det;
        hit = hit & (t >= tmin_) & (t < t_limit);
        if (L::none(hit)) return hit;
        const Mask near_origin = t <= t_rounding_bound(ax, ay, bx, by, cx, cy, a.z, b.z, c.z, u, v, w, inv_det);
        if (L::any(hit & near_origin)) {
            const auto [tri_a, tri_b, tri_c] = world_corners();
            hit = detail::drop_crossings_before_tmin(hit, near_origin, tri_a, tri_b, tri_c, origin_, dir_, tmin_);
            if (L::none(hit)) return hit;
        }
        if constexpr (ZeroArea == ZeroAreaTriangles::dropped_by_test) {
            const auto [tri_a, tri_b, tri_c] = world_corners();
            hit = detail::drop_zero_area(hit, tri_a, tri_b, tri_c);
            if (L::none(hit)) return hit;
        }
        out = {t, v * inv_det, w * inv_det};
        return hit;
    }

    /// A bound on the rounding error of t, after the analysis of pbrt-v3 (section 3.9.6) for this
    /// same test, from the magnitudes of the sheared corners (x, y and the unscaled z, in units of
    /// length) and of the edge functions. pbrt adds z to x and y after scaling it by 1 / dir.z,
    /// which assumes a unit direction; here z stays in units of length until t is formed, so the
    /// bound holds for any |dir| (the stress cases trace rays of length 1e-4 at meshes of size
    /// 1e-4). A hit whose t lies within the bound of 0 may really cross the plane behind the origin:
    /// from a point offset off a surface (core/ray_offset.h), the surface's coplanar neighbours,
    /// far larger than the offset, come out hit at t near 0 and would shadow it. Such hits are
    /// decided again in double (detail::drop_crossings_before_tmin) rather than dropped, since
    /// the bound also exceeds t on slivers far from the origin (det near 0), which must stay hit
    /// for the mesh to stay watertight. It is computed only when some lane hits, so the misses
    /// that make up most tests do not pay for it.
    T t_rounding_bound(const T& ax, const T& ay, const T& bx, const T& by, const T& cx, const T& cy, const T& az,
                       const T& bz, const T& cz, const T& u, const T& v, const T& w, const T& inv_det) const {
        const auto largest = [](const T& p, const T& q, const T& r) {
            return L::max(L::abs(p), L::max(L::abs(q), L::abs(r)));
        };
        const T max_x = largest(ax, bx, cx), max_y = largest(ay, by, cy), max_z = largest(az, bz, cz);
        const T max_zt = L::abs(sz_) * max_z;  // in units of t
        const T max_e = largest(u, v, w);
        const T delta_x = T(rounding_gamma(5)) * (max_x + max_z), delta_y = T(rounding_gamma(5)) * (max_y + max_z);
        const T delta_e = T(2.0f) * (T(rounding_gamma(2)) * max_x * max_y + delta_y * max_x + delta_x * max_y);
        const T delta_zt = T(rounding_gamma(3)) * max_zt;
        return T(3.0f) * (T(rounding_gamma(3)) * max_e * max_zt + delta_e * max_zt + delta_zt * max_e) * L::abs(inv_det);
    }

    Vec3T<T> origin_, dir_;
    T tmin_;
    typename L::AxisPermutation axes_;
    Vec3T<T> origin_in_ray_axes_;
    T sx_, sy_, sz_;
};

template <class T>
class TriangleIntersectorT<TriangleTest::moller_trumbore, T> {
    using L = Lanes<T>;

public:
    using Mask = typename L::Mask;

    TriangleIntersectorT(const Vec3T<T>& origin, const Vec3T<T>& dir, T tmin)
        : origin_(origin), dir_(dir), tmin_(tmin) {}
    explicit TriangleIntersectorT(const Ray& ray) requires std::same_as<T, float>
        : TriangleIntersectorT(ray.origin, ray.dir, ray.tmin) {}

    Mask intersect(const Triangle& tri, T t_limit, TriangleHitT<T>& out) const {
        return intersect(Vec3T<T>(tri.a), Vec3T<T>(tri.b), Vec3T<T>(tri.c), t_limit, out);
    }

    template <ZeroAreaTriangles ZeroArea = ZeroAreaTriangles::dropped_by_test>
    Mask intersect(const Vec3T<T>& a, const Vec3T<T>& b, const Vec3T<T>& c, T t_limit, TriangleHitT<T>& out) const {
        const T zero(0.0f), one(1.0f);
        const Vec3T<T> e1 = b - a, e2 = c - a;
        const Vec3T<T> p = cross(dir_, e2);
        const T det = dot(e1, p);
        Mask hit = det != zero;
        if (L::none(hit)) return hit;
        const T inv_det = one / det;
        const Vec3T<T> s = origin_ - a;
        const T u = dot(s, p) * inv_det;
        hit = hit & !((u < zero) | (u > one));  // negated: a NaN u is left to the t test
        if (L::none(hit)) return hit;
        const Vec3T<T> q = cross(s, e1);
        const T v = dot(dir_, q) * inv_det;
        hit = hit & !((v < zero) | (u + v > one));
        if (L::none(hit)) return hit;
        const T t = dot(e2, q) * inv_det;
        hit = hit & (t >= tmin_) & (t < t_limit);
        if (L::none(hit)) return hit;
        if constexpr (ZeroArea == ZeroAreaTriangles::dropped_by_test) {
            hit = detail::drop_zero_area(hit, a, b, c);
            if (L::none(hit)) return hit;
        }
        out = {t, u, v};
        return hit;
    }

private:
    Vec3T<T> origin_, dir_;
    T tmin_;
};

}  // namespace trident
