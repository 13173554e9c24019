#pragma once
// Every triangle against every ray, in single precision with the same triangle tests as the
// trees: the baseline a structure must beat, and the smallest example of the structure interface
// (build, intersect, occluded, stats). It tests no boxes, so the slab-test flag the trees take
// (core/slab_test.h) is accepted and changes nothing. Its packet kernels are instantiated in
// brute_force.cpp, as the trees' are in theirs (accel/packet_kernels.h).
#include <vector>

#include "accel/accel_stats.h"
#include "accel/packet_kernels.h"
#include "core/intersect_triangle.h"
#include "core/mesh.h"
#include "core/slab_test.h"
#include "simd/packet.h"

namespace trident {

class BruteForce {
public:
    static BruteForce build(const Mesh& mesh);

    template <TriangleTest Test, SlabTest = SlabTest::robust, class Counters>
    Hit intersect(const Ray& ray, Counters& counters) const {
        const TriangleIntersector<Test> isect(ray);
        Hit best;
        best.t = ray.tmax;
        TriangleHit h;
        for (std::size_t i = 0; i < triangles_.size(); ++i) {
            counters.test_triangle();
            if (isect.intersect(triangles_[i], best.t, h)) best = {static_cast<TriangleId>(i), h.t, h.u, h.v};
        }
        if (!best.is_hit()) best.t = kInfinity;
        return best;
    }

    template <TriangleTest Test, SlabTest = SlabTest::robust, class Counters>
    bool occluded(const Ray& ray, Counters& counters) const {
        const TriangleIntersector<Test> isect(ray);
        TriangleHit h;
        for (const Triangle& tri : triangles_) {
            counters.test_triangle();
            if (isect.intersect(tri, ray.tmax, h)) return true;
        }
        return false;
    }

    template <TriangleTest Test, SlabTest = SlabTest::robust, class Arch, class Counters>
    void intersect(const RayPacket<Arch>& rays, HitPacket<Arch>& hits, Counters& counters,
                   int /*single_ray_lanes*/ = kDefaultSingleRayLanes) const {
        const auto isect = packet_intersector<Test>(rays);
        using Float = typename RayPacket<Arch>::Float;
        TriangleHitT<Float> h{Float(0.0f), Float(0.0f), Float(0.0f)};
        for (std::size_t i = 0; i < triangles_.size(); ++i) {
            counters.test_triangle();
            hits.record(isect.intersect(triangles_[i], hits.t, h), static_cast<TriangleId>(i), h);
        }
    }

    template <TriangleTest Test, SlabTest = SlabTest::robust, class Arch, class Counters>
    typename RayPacket<Arch>::Mask occluded(const RayPacket<Arch>& rays, Counters& counters,
                                            int /*single_ray_lanes*/ = kDefaultSingleRayLanes) const {
        const auto isect = packet_intersector<Test>(rays);
        using Float = typename RayPacket<Arch>::Float;
        TriangleHitT<Float> h{Float(0.0f), Float(0.0f), Float(0.0f)};
        typename RayPacket<Arch>::Mask blocked(false);
        for (const Triangle& tri : triangles_) {
            counters.test_triangle();
            blocked = blocked | isect.intersect(tri, rays.tmax, h);
            if (xsimd::all(blocked | !rays.active)) break;
        }
        return blocked & rays.active;
    }

    Hit intersect(const Ray& ray) const { NoCounters c; return intersect<TriangleTest::watertight>(ray, c); }
    bool occluded(const Ray& ray) const { NoCounters c; return occluded<TriangleTest::watertight>(ray, c); }
    const AccelStats& stats() const { return stats_; }

private:
    std::vector<Triangle> triangles_;
    AccelStats stats_;
};

}  // namespace trident
