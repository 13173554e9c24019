#pragma once
// Ray/box test by slabs (Kay and Kajiya 1986), made robust after Ize, "Robust BVH Ray Traversal"
// (JCGT 2(2), 2013), and written once over a value type T: float for one ray, an xsimd batch for
// a packet (one ray per lane, reached through Lanes<T> of core/lanes.h).
//
// Rounding: with the reciprocal direction precomputed, a slab distance (plane - origin) * inv_dir
// carries three roundings (the difference, the reciprocal, the product). Ize shows that scaling
// every far distance by 1 + 2 gamma(3) makes the interval conservative, so a ray that touches a
// box in exact arithmetic is never rejected and no hit slips between two boxes sharing a face.
// Distances behind the origin are not widened: rays start at t_min >= 0.
//
// Zero direction components need no branch: 1/+0 = +inf and 1/-0 = -inf, so a ray parallel to a
// slab gets -inf/+inf on that axis. The classic trap is an origin exactly on a slab plane, where
// (plane - origin) is 0 and 0 * inf would be NaN. Such a zero offset is replaced by a tiny one
// that puts the origin just inside the slab (the box is closed: a point on its face is inside),
// so no NaN can arise. For a nonzero direction the replacement only moves that distance outward
// by tiny * |inv_dir|, which keeps the test conservative.
//
// SlabTest::fast drops both safeguards: the plain Kay–Kajiya test, as most tracers ship it, kept
// to measure what robustness costs (issue 8). It can reject a box the ray touches only within
// rounding, and gives NaN (a miss) for an origin on a slab plane of an axis the ray runs parallel to.
#include <limits>
#include <optional>
#include <string_view>

#include "core/lanes.h"
#include "core/ray.h"
#include "core/rounding.h"
#include "core/vec3.h"

namespace trident {

/// Robust (the default) or fast box tests, a compile-time choice threaded through every traversal.
enum class SlabTest { robust, fast };

inline const char* to_string(SlabTest slabs) { return slabs == SlabTest::robust ? "robust" : "fast"; }

inline std::optional<SlabTest> parse_slab_test(std::string_view name) {
    if (name == "robust") return SlabTest::robust;
    if (name == "fast") return SlabTest::fast;
    return std::nullopt;
}

/// What the slab test needs of a ray, computed once per ray (or packet).
template <class T>
struct SlabRayT {
    Vec3T<T> origin;
    Vec3T<T> inv_dir;  // +-inf where the direction component is +-0

    SlabRayT(const Vec3T<T>& origin_, const Vec3T<T>& dir)
        : origin(origin_), inv_dir(T(1.0f) / dir.x, T(1.0f) / dir.y, T(1.0f) / dir.z) {}
};
using SlabRay = SlabRayT<float>;

namespace detail {

/// Ize's widening of every far distance: three roundings in (plane - origin) * inv_dir.
inline constexpr float kFarScale = 1.0f + 2.0f * rounding_gamma(3);

template <class T>
struct SlabInterval {
    T near, far;
};

/// The ray's parameter interval inside one slab [lo, hi], the far end widened when robust.
template <SlabTest Slabs = SlabTest::robust, class T>
SlabInterval<T> slab_interval(T lo, T hi, T origin, T inv_dir) {
    using L = Lanes<T>;
    const T to_lo = lo - origin, to_hi = hi - origin;
    if constexpr (Slabs == SlabTest::robust) {
        const T zero(0.0f), tiny(std::numeric_limits<float>::min());
        const T t_lo = L::select(to_lo == zero, -tiny, to_lo) * inv_dir;
        const T t_hi = L::select(to_hi == zero, tiny, to_hi) * inv_dir;
        return {L::min(t_lo, t_hi), L::max(t_lo, t_hi) * T(kFarScale)};
    } else {
        const T t_lo = to_lo * inv_dir, t_hi = to_hi * inv_dir;
        return {L::min(t_lo, t_hi), L::max(t_lo, t_hi)};
    }
}

/// The robust test with the slab's planes already ordered along the ray: near_plane is lo where
/// the ray's direction is positive and hi where it is negative (from the sign of inv_dir, so -0
/// counts as negative), far_plane the other. No comparison or select is needed for the zero
/// offsets: an origin on a plane the ray runs along gives 0 * inf = NaN, and min and max return
/// their second operand when either is NaN (core/lanes.h), so such a slab leaves entry or exit
/// as they were: the ray lies inside that closed slab. Where nothing is NaN the result is the
/// robust interval of slab_interval, so both forms accept the same boxes; this one saves the
/// compare-and-select pair per plane in the single-ray BVH's box test. SlabTest::fast leaves out
/// the widening (the wide BVH's fast variant: with ordered planes an empty box [+inf, -inf] is
/// still entered by no ray, which the unordered fast formula cannot promise).
template <SlabTest Slabs = SlabTest::robust, class T>
void clip_to_ordered_slab(T near_plane, T far_plane, T origin, T inv_dir, T& entry, T& exit) {
    using L = Lanes<T>;
    entry = L::max((near_plane - origin) * inv_dir, entry);
    const T far = (far_plane - origin) * inv_dir;
    exit = L::min(Slabs == SlabTest::robust ? far * T(kFarScale) : far, exit);
}

/// Narrows [entry, exit] to the ray's interval inside one slab [lo, hi].
template <SlabTest Slabs = SlabTest::robust, class T>
void clip_to_slab(T lo, T hi, T origin, T inv_dir, T& entry, T& exit) {
    const SlabInterval<T> slab = slab_interval<Slabs>(lo, hi, origin, inv_dir);
    entry = Lanes<T>::max(entry, slab.near);
    exit = Lanes<T>::min(exit, slab.far);
}

}  // namespace detail

/// The ray's interval inside the closed, non-empty box [lo, hi]: [t_min, t_max] narrowed to
/// [t_entry, t_exit], the exit widened as above (a kd-tree clips its rays to the scene box so).
/// The interval is not empty where the mask is set.
template <SlabTest Slabs = SlabTest::robust, class T>
typename Lanes<T>::Mask clip_to_box(const SlabRayT<T>& ray, const Vec3T<T>& lo, const Vec3T<T>& hi, T t_min, T t_max,
                                    T& t_entry, T& t_exit) {
    t_entry = t_min;
    t_exit = t_max;
    detail::clip_to_slab<Slabs>(lo.x, hi.x, ray.origin.x, ray.inv_dir.x, t_entry, t_exit);
    detail::clip_to_slab<Slabs>(lo.y, hi.y, ray.origin.y, ray.inv_dir.y, t_entry, t_exit);
    detail::clip_to_slab<Slabs>(lo.z, hi.z, ray.origin.z, ray.inv_dir.z, t_entry, t_exit);
    return t_entry <= t_exit;
}

/// Whether the ray's interval [t_min, t_max] meets the closed, non-empty box [lo, hi]. Writes the
/// entry distance, max(t_min, where the ray enters the box), to t_entry (meaningful where it hits).
template <SlabTest Slabs = SlabTest::robust, class T>
typename Lanes<T>::Mask intersect_slabs(const SlabRayT<T>& ray, const Vec3T<T>& lo, const Vec3T<T>& hi, T t_min,
                                        T t_max, T& t_entry) {
    T t_exit;
    return clip_to_box<Slabs>(ray, lo, hi, t_min, t_max, t_entry, t_exit);
}

}  // namespace trident
