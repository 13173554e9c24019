#pragma once
// The octree of the reference study: every node split by the three planes through its centre
// into 8 cubes, down to a maximum depth or a minimum triangle count; triangles referenced by
// every cell they overlap; traced with the parametric algorithm of Revelles, Ureña and Lastra
// (WSCG 2000). Building: octree_build.h; layout: octree_node.h; traversal: octree_traversal.h,
// for ray packets octree_packet.h.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "accel/accel_stats.h"
#include "accel/octree/octree_build.h"
#include "accel/octree/octree_node.h"
#include "accel/octree/octree_traversal.h"
#include "accel/packet_kernels.h"
#include "core/intersect_triangle.h"
#include "core/mesh.h"
#include "simd/packet.h"

namespace trident {

class Octree {
public:
    /// Throws std::invalid_argument on options out of range (validate()).
    static Octree build(const Mesh& mesh, const OctreeOptions& options = {});

    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Counters>
    Hit intersect(const Ray& ray, Counters& counters) const {
        return traverse_octree<OctreeQuery::closest_hit, Test, Slabs>(view(), ray, counters);
    }
    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Counters>
    bool occluded(const Ray& ray, Counters& counters) const {
        return traverse_octree<OctreeQuery::any_hit, Test, Slabs>(view(), ray, counters).is_hit();
    }
    Hit intersect(const Ray& ray) const {
        NoCounters c;
        return intersect<TriangleTest::watertight>(ray, c);
    }
    bool occluded(const Ray& ray) const {
        NoCounters c;
        return occluded<TriangleTest::watertight>(ray, c);
    }

    /// Ray packets (octree_packet.h): per active lane, the same hit as intersect(ray) bit for bit,
    /// into `hits` constructed from `rays`; the same answer as occluded(ray). Subtrees that at
    /// most `single_ray_lanes` lanes enter are walked lane by lane (the default:
    /// kOctreeSingleRayLanes). Counters count per packet (per ray for lanes traced singly).
    /// Defined in octree_packet.h, instantiated in octree_packet_kernels.cpp: callers go through
    /// PacketKernels (accel/packet_kernels.h).
    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Arch, class Counters>
    void intersect(const RayPacket<Arch>& rays, HitPacket<Arch>& hits, Counters& counters,
                   int single_ray_lanes = kDefaultSingleRayLanes) const;
    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Arch, class Counters>
    typename RayPacket<Arch>::Mask occluded(const RayPacket<Arch>& rays, Counters& counters,
                                            int single_ray_lanes = kDefaultSingleRayLanes) const;

    const AccelStats& stats() const { return stats_; }
    /// Empty unless the build left something out or stopped splitting early (to be printed).
    const std::string& warning() const { return warning_; }

    // The flattened layout, for packet traversals and tests.
    std::span<const OctreeNode> nodes() const { return nodes_; }
    std::span<const std::uint32_t> triangle_indices() const { return triangle_indices_; }
    std::span<const Triangle> triangles() const { return triangles_; }          // Morton order
    std::span<const TriangleId> triangle_ids() const { return triangle_ids_; }  // file order of each
    const OctreeCube& cube() const { return cube_; }
    int max_depth() const { return max_depth_; }  // the limit the build used
    OctreeView view() const { return {nodes_, triangle_indices_, triangles_, triangle_ids_, cube_}; }

private:
    std::vector<OctreeNode> nodes_;
    std::vector<std::uint32_t> triangle_indices_;
    std::vector<Triangle> triangles_;
    std::vector<TriangleId> triangle_ids_;
    OctreeCube cube_;
    int max_depth_ = 0;
    AccelStats stats_;
    std::string warning_;
};

}  // namespace trident
