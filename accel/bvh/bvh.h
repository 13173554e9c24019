#pragma once
// Bounding volume hierarchy over the triangles of a mesh (object subdivision, binary, SAH),
// flattened depth-first (bvh_node.h) with the triangles copied into leaf order, so a traversal
// reads three arrays and follows no pointers: the node array, the leaf-order corners, and the
// leaf-order file ids.
//
// The traversal is one function with compile-time flags (closest or any hit, triangle test, robust
// or fast slab test, counters). It tests both children's boxes at an interior node with the slab test
// (core/slab_test.h, three axes at once: node_box_test.h), goes to the near child first by the
// sign of the ray direction on the node's split axis, and stacks the far one with its entry
// distance, so that a popped node starting beyond the closest hit found meanwhile is skipped.
// Ray packets walk the same tree together (bvh_packet.h) and hand subtrees few of their lanes
// need to this traversal; callers trace them through PacketKernels (accel/packet_kernels.h).
#include <cassert>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "accel/accel_stats.h"
#include "accel/bvh/bvh_node.h"
#include "accel/bvh/bvh_options.h"
#include "accel/bvh/node_box_test.h"
#include "accel/packet_kernels.h"
#include "core/huge_page_array.h"
#include "core/intersect_triangle.h"
#include "core/mesh.h"
#include "simd/packet.h"

namespace trident {

namespace bvh {

/// The binary tree without the corners copied into leaf order: what Bvh::build and the wide BVH's
/// collapse (wide_collapse.h) start from.
struct BinaryTree {
    HugePageArray<BvhNode> nodes;         // depth-first, root first
    HugePageArray<TriangleId> leaf_ids;  // leaves' triangles in leaf order (file-order ids)
};

/// Builds with oneTBB on the caller's threads; the result does not depend on their number.
/// BvhBuilder::automatic builds binned, as the binary BVH, the study's, always is (WideBvh::build
/// resolves it per mesh before calling this). Throws as Bvh::build does.
BinaryTree build_binary_tree(const Mesh& mesh, const BvhOptions& options);

}  // namespace bvh

class Bvh {
public:
    /// Builds with oneTBB on the caller's threads; the result does not depend on their number.
    /// Throws std::invalid_argument for invalid options, std::length_error for a mesh whose
    /// triangles cannot be numbered in 32 bits.
    static Bvh build(const Mesh& mesh, const BvhOptions& options = {});

    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Counters>
    Hit intersect(const Ray& ray, Counters& counters) const {
        return traverse<false, Test, Slabs>(ray, 0, counters);
    }
    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Counters>
    bool occluded(const Ray& ray, Counters& counters) const {
        return traverse<true, Test, Slabs>(ray, 0, counters).is_hit();
    }
    Hit intersect(const Ray& ray) const {
        NoCounters c;
        return intersect<TriangleTest::watertight>(ray, c);
    }
    bool occluded(const Ray& ray) const {
        NoCounters c;
        return occluded<TriangleTest::watertight>(ray, c);
    }

    /// Ray packets (bvh_packet.h): per active lane with tmin <= tmax, the closest hit into `hits`
    /// (constructed from `rays`; other lanes are left as they are), or whether anything is hit.
    /// A lane gets intersect(ray)'s hit bit for bit, except that of two triangles hit at exactly
    /// its t it may keep the other one (bvh_packet.h says when). Subtrees that at most
    /// `single_ray_lanes` lanes need are traced ray by ray; the default is the width's measured best.
    /// Counters count per packet (and per ray in the subtrees traced ray by ray). Defined in
    /// bvh_packet.h, instantiated in bvh_packet_kernels.cpp: callers go through PacketKernels.
    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Arch, class Counters>
    void intersect(const RayPacket<Arch>& rays, HitPacket<Arch>& hits, Counters& counters,
                   int single_ray_lanes = kDefaultSingleRayLanes) const;
    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Arch, class Counters>
    typename RayPacket<Arch>::Mask occluded(const RayPacket<Arch>& rays, Counters& counters,
                                            int single_ray_lanes = kDefaultSingleRayLanes) const;

    const AccelStats& stats() const { return stats_; }
    const BvhOptions& options() const { return options_; }

    /// The flattened layout, for tests and for packet traversals: nodes depth-first (root first,
    /// left child next to its parent), and per leaf-order slot the triangle's corners and its
    /// file-order id; a leaf covers slots [first_triangle, first_triangle + triangle_count).
    std::span<const BvhNode> nodes() const { return nodes_; }
    std::span<const Triangle> leaf_triangles() const { return triangles_; }
    std::span<const TriangleId> leaf_triangle_ids() const { return triangle_ids_; }

private:
    /// The single-ray traversal of the subtree at `subtree` (the root: 0).
    template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Counters>
    Hit traverse(const Ray& ray, std::uint32_t subtree, Counters& counters) const;

    template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
    typename RayPacket<Arch>::Mask traverse_packet(const RayPacket<Arch>& rays, HitPacket<Arch>& hits,
                                                   Counters& counters, int single_ray_lanes) const;

    HugePageArray<BvhNode> nodes_;
    HugePageArray<Triangle> triangles_;
    HugePageArray<TriangleId> triangle_ids_;
    BvhOptions options_;
    AccelStats stats_;
};

/// Counters: nodes_visited counts node boxes tested (the root's included), triangles_tested the
/// triangle tests.
template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Counters>
Hit Bvh::traverse(const Ray& ray, std::uint32_t subtree, Counters& counters) const {
    Hit best;
    if (nodes_.empty()) return best;
    const bvh::NodeBoxTest<Slabs> box_test(ray);
    const TriangleIntersector<Test> triangle_test(ray);
    const bool dir_negative[3] = {ray.dir.x < 0.0f, ray.dir.y < 0.0f, ray.dir.z < 0.0f};
    float t_limit = ray.tmax;  // hits count strictly before it

    struct StackEntry {
        std::uint32_t node;
        float t_entry;
    };
    StackEntry stack[kBvhMaxDepth];  // one entry per level at most: the builder bounds the depth
    std::uint32_t stack_size = 0;

    float t_root;
    counters.visit_node();
    if (!box_test.enters(nodes_[subtree], ray.tmin, t_limit, t_root)) return best;
    std::uint32_t current = subtree;
    for (;;) {
        const BvhNode& node = nodes_[current];
        if (node.is_leaf()) {
            const std::uint32_t end = node.first_triangle() + node.triangle_count();
            for (std::uint32_t i = node.first_triangle(); i != end; ++i) {
                counters.test_triangle();
                TriangleHit h;
                if (triangle_test.intersect(triangles_[i], t_limit, h)) {
                    best = {triangle_ids_[i], h.t, h.u, h.v};
                    if constexpr (AnyHit) return best;
                    t_limit = h.t;
                }
            }
        } else {
            std::uint32_t near = current + 1, far = node.right_child();
            if (dir_negative[node.split_axis()]) std::swap(near, far);
            float t_near, t_far;
            counters.visit_node();  // two boxes tested, in one step
            counters.visit_node();
            const unsigned entered = box_test.enters_pair(nodes_[near], nodes_[far], ray.tmin, t_limit, t_near, t_far);
            const bool hit_near = entered & 1u, hit_far = entered & 2u;
            if (hit_near) {
                if (hit_far) {
                    assert(stack_size < kBvhMaxDepth);
                    stack[stack_size++] = {far, t_far};
                }
                current = near;
                continue;
            }
            if (hit_far) {
                current = far;
                continue;
            }
        }
        for (;;) {  // pop the next node that can still hold a closer hit
            if (stack_size == 0) return best;
            const StackEntry entry = stack[--stack_size];
            if (entry.t_entry <= t_limit) {
                current = entry.node;
                break;
            }
        }
    }
}

}  // namespace trident
