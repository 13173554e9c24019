#pragma once
// Ray packets: up to N rays in structure-of-arrays form, one per lane of an xsimd batch, with what
// every traversal step needs computed once per packet (Embree's TravRayK): the reciprocal
// direction (in the slab test's form), per-axis sign masks and whether all active lanes share one
// octant. HitPacket keeps the closest hits, which simd/hit_lanes.h writes out as scalar Hits. Lane
// i of a packet test equals the scalar test on ray i bit for bit (core/lanes.h says what that
// takes).
// Why the build is tied to -march=native, and how one binary could serve SSE4.2, AVX2 and AVX-512
// CPUs: simd/README.md.
#include <cstddef>
#include <cstdint>
#include <span>
#include <xsimd/xsimd.hpp>

#include "core/intersect_triangle.h"
#include "core/ray.h"
#include "core/slab_test.h"
#include "simd/lanes.h"
#include "simd/mask.h"
#include "simd/ray_lanes.h"

namespace trident {

template <class Arch>
struct RayPacket {
    using Float = xsimd::batch<float, Arch>;
    using Mask = xsimd::batch_bool<float, Arch>;
    static constexpr std::size_t width = Float::size;
    static constexpr int kMixedOctant = -1;

    Vec3T<Float> origin, dir;
    Float tmin, tmax;          // inactive lanes hold [+inf, -inf], which nothing intersects
    Mask active;               // the lanes loaded from a ray
    SlabRayT<Float> slab;      // origin and 1 / dir (+-inf where dir is +-0) for intersect_slabs
    Vec3T<Mask> dir_negative;  // per axis: 1 / dir < 0, so -0 counts as negative, as its reciprocal does
    int octant;                // bit a = dir_negative[a] when every active lane agrees, else kMixedOctant

    /// Lane i holds rays[i]; 1 <= rays.size() <= width. Lanes past the count are inactive and
    /// copy the first ray's origin and direction, so they hold no NaN and keep its octant.
    explicit RayPacket(std::span<const Ray> rays) : RayPacket(simd::RayLanes<Arch>(rays)) {}
    /// Lane i holds rays[index[i]]; 1 <= index.size() <= width.
    RayPacket(std::span<const Ray> rays, std::span<const std::size_t> index)
        : RayPacket(simd::RayLanes<Arch>(rays, index)) {}

    /// Rays already in lanes: those of `live` from `origins` along `dirs` over [tmins, tmaxs];
    /// the other lanes become inactive ([+inf, -inf]) and must hold finite origins and directions.
    RayPacket(const Vec3T<Float>& origins, const Vec3T<Float>& dirs, const Float& tmins, const Float& tmaxs,
              const Mask& live)
        : origin(origins),
          dir(dirs),
          tmin(xsimd::select(live, tmins, Float(kInfinity))),
          tmax(xsimd::select(live, tmaxs, Float(-kInfinity))),
          active(live),
          slab(origin, dir),
          dir_negative(slab.inv_dir.x < Float(0.0f), slab.inv_dir.y < Float(0.0f), slab.inv_dir.z < Float(0.0f)),
          octant(shared_octant(dir_negative, active)) {}

    bool shares_octant() const { return octant != kMixedOctant; }

private:
    explicit RayPacket(const simd::RayLanes<Arch>& lanes)
        : RayPacket({lanes.field[0], lanes.field[1], lanes.field[2]}, {lanes.field[3], lanes.field[4], lanes.field[5]},
                    lanes.field[6], lanes.field[7], lanes.live) {}

    static int shared_octant(const Vec3T<Mask>& negative, const Mask& active) {
        const std::uint32_t active_bits = simd::mask_bits(active);
        int octant = 0;
        for (int axis = 0; axis < 3; ++axis) {
            const std::uint32_t negative_bits = simd::mask_bits(negative[axis]) & active_bits;
            if (negative_bits == active_bits)
                octant |= 1 << axis;
            else if (negative_bits != 0)
                return kMixedOctant;
        }
        return octant;
    }
};

/// The triangle test for every lane of a packet at once.
template <TriangleTest Test, class Arch>
TriangleIntersectorT<Test, xsimd::batch<float, Arch>> packet_intersector(const RayPacket<Arch>& rays) {
    return {rays.origin, rays.dir, rays.tmin};
}

template <class Arch>
struct HitPacket {
    using Float = xsimd::batch<float, Arch>;
    using Mask = xsimd::batch_bool<float, Arch>;
    using Ids = xsimd::batch<std::uint32_t, Arch>;
    static constexpr std::size_t width = Float::size;

    Ids triangle;  // file-order index, kNoTriangle until the lane records a hit
    Float t;       // the closest hit so far, else the ray's tmax: the limit for the next test
    Float u, v;

    explicit HitPacket(const RayPacket<Arch>& rays) : triangle(kNoTriangle), t(rays.tmax), u(0.0f), v(0.0f) {}

    /// The lanes in `hit` take triangle `id` at `h`.
    void record(const Mask& hit, TriangleId id, const TriangleHitT<Float>& h) {
        triangle = simd::select_index(hit, Ids(id), triangle);
        t = xsimd::select(hit, h.t, t);
        u = xsimd::select(hit, h.u, u);
        v = xsimd::select(hit, h.v, v);
    }
};

}  // namespace trident
