#pragma once
// Customization points that let one formula serve one ray (float) and a packet of rays (an xsimd
// batch, one ray per lane). The geometry tests are written over a value type T and reach
// everything that is not plain arithmetic or comparison through Lanes<T>: Lanes<float> is here,
// Lanes<xsimd::batch<float, Arch>> in simd/lanes.h (core does not know xsimd; the specialization
// must be visible where a packet instantiation happens).
//
// A packet lane must equal the scalar result bit for bit, so both sides round alike: min and max
// follow the SSE rule (the second operand when either is NaN), selects and abs are exact, and no
// multiply-add is fused. The last needs -ffp-contract=off (CMakeLists.txt): under GCC's default
// (fast) the scalar and the vector code fuse different products, and hits, not just last bits,
// differ (tests/simd checks this).
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "core/vec3.h"

namespace trident {

template <class T>
struct Lanes;  // specialized per value type; see Lanes<float> for the members every one has

template <>
struct Lanes<float> {
    using Mask = bool;
    static constexpr std::size_t width = 1;
    /// Lane values in memory, for work done lane by lane (rare fallbacks).
    using Array = std::array<float, 1>;

    static float select(bool mask, float if_true, float if_false) { return mask ? if_true : if_false; }
    static float abs(float x) { return std::abs(x); }
    static float sqrt(float x) { return std::sqrt(x); }           // correctly rounded, as the batch's
    static float min(float a, float b) { return a < b ? a : b; }  // minss: b when either is NaN
    static float max(float a, float b) { return a > b ? a : b; }  // maxss: b when either is NaN
    static bool any(bool mask) { return mask; }
    static bool none(bool mask) { return !mask; }
    /// Bit i set when lane i is set.
    static std::uint32_t bits(bool mask) { return mask ? 1u : 0u; }
    static Array to_array(float x) { return {x}; }
    static float from_array(const Array& lanes) { return lanes[0]; }

    /// The watertight test's per-ray axis permutation (Woop, Benthin and Wald 2013, section 3):
    /// z becomes the axis where |dir| is largest (ties to the lower axis), x and y follow
    /// cyclically and swap when dir is negative along the new z, which keeps the winding.
    struct AxisPermutation {
        int kx, ky, kz;
        Vec3f apply(const Vec3f& v) const { return {v[kx], v[ky], v[kz]}; }
    };
    static AxisPermutation major_axis_to_z(const Vec3f& dir) {
        const int kz = largest_abs_axis(dir);
        return permutation_to_z(kz, dir[kz] < 0.0f);
    }
    /// The permutation that makes axis kz the new z, x and y swapped when swap_xy.
    static AxisPermutation permutation_to_z(int kz, bool swap_xy) {
        const int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
        return swap_xy ? AxisPermutation{ky, kx, kz} : AxisPermutation{kx, ky, kz};
    }
};

}  // namespace trident
