#pragma once
// The kd-tree: axis-aligned split planes chosen by the surface area heuristic over split-plane
// events (the reference study, after pbrt), built in O(N log N) after Wald and Havran (2006), and
// flattened into 8-byte nodes. Building: kd_build.h; options: kd_options.h; layout: kd_node.h;
// traversal: kd_traversal.h (single rays), kd_packet.h (ray packets).
#include <span>
#include <vector>

#include "accel/accel_stats.h"
#include "accel/kdtree/kd_node.h"
#include "accel/kdtree/kd_options.h"
#include "accel/kdtree/kd_traversal.h"
#include "accel/packet_kernels.h"
#include "core/intersect_triangle.h"
#include "core/mesh.h"
#include "simd/packet.h"

namespace trident {

class KdTree {
public:
    /// Throws std::invalid_argument on options out of range, std::length_error when the tree
    /// outgrows the 28-bit indices of KdNode.
    static KdTree build(const Mesh& mesh, const KdTreeOptions& options = {});

    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Counters>
    Hit intersect(const Ray& ray, Counters& counters) const {
        return traverse_kdtree<KdQuery::closest_hit, Test, Slabs>(view(), ray, counters);
    }
    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Counters>
    bool occluded(const Ray& ray, Counters& counters) const {
        return traverse_kdtree<KdQuery::any_hit, Test, Slabs>(view(), ray, counters).is_hit();
    }
    Hit intersect(const Ray& ray) const {
        NoCounters c;
        return intersect<TriangleTest::watertight>(ray, c);
    }
    bool occluded(const Ray& ray) const {
        NoCounters c;
        return occluded<TriangleTest::watertight>(ray, c);
    }

    /// Ray packets (kd_packet.h): per active lane with tmin <= tmax, the closest hit into `hits`
    /// (constructed from `rays`; other lanes are left as they are) or whether anything is hit,
    /// equal to intersect(ray) / occluded(ray) bit for bit. Subtrees that at most
    /// `single_ray_lanes` lanes need are walked ray by ray; the default is the measured break-even
    /// of the width. Defined in kd_packet.h, instantiated in kd_packet_kernels.cpp: callers go
    /// through PacketKernels (accel/packet_kernels.h).
    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Arch, class Counters>
    void intersect(const RayPacket<Arch>& rays, HitPacket<Arch>& hits, Counters& counters,
                   int single_ray_lanes = kDefaultSingleRayLanes) const;
    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Arch, class Counters>
    typename RayPacket<Arch>::Mask occluded(const RayPacket<Arch>& rays, Counters& counters,
                                            int single_ray_lanes = kDefaultSingleRayLanes) const;

    const AccelStats& stats() const { return stats_; }

    // The flattened layout, for packet traversals and tests.
    std::span<const KdNode> nodes() const { return nodes_; }
    std::span<const TriangleId> leaf_triangles() const { return leaf_triangles_; }  // indices into triangles()
    std::span<const Triangle> triangles() const { return triangles_; }          // the builder's order, finite ones only
    std::span<const TriangleId> triangle_ids() const { return triangle_ids_; }  // file index of each
    const Aabb& bounds() const { return bounds_; }
    KdTreeView view() const { return {nodes_, leaf_triangles_, triangles_, triangle_ids_, bounds_}; }

private:
    std::vector<KdNode> nodes_;
    std::vector<TriangleId> leaf_triangles_;
    std::vector<Triangle> triangles_;
    std::vector<TriangleId> triangle_ids_;
    Aabb bounds_;
    AccelStats stats_;
};

}  // namespace trident
