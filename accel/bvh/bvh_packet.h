#pragma once
// Ray packet traversal of the BVH: the whole packet walks the tree once, with one fixed stack
// (Wald, Slusallek, Benthin and Wagner, "Interactive Rendering with Coherent Ray Tracing", EG 2001),
// in the ordered and masked form of Embree's hybrid traversal, which hands subtrees that only a few
// lanes still need to the single-ray traversal (Benthin, Wald, Woop, Ernst and Mark, "Combining
// Single and Packet-Ray Tracing for Arbitrary Ray Distributions on the Intel MIC Architecture",
// IEEE TVCG 18(9), 2012).
//
// A node is visited by the lanes whose slab test (core/slab_test.h, one lane per ray) enters it
// before their closest hit so far. At an interior node the packet tests both children, goes to the
// near one and stacks the far one with its per-lane entry distances, so that when it is popped only
// the lanes that still need it (entry <= closest hit) visit it, and none at all skips it. Near is
// decided by the visiting lanes' majority sign on the node's split axis. A leaf tests each of its
// triangles against all visiting lanes at once.
//
// Per lane, every decision is the single-ray traversal's (bvh.h): the same slab test with the same
// limit, the same pruning rule, the same triangle test. A lane whose direction agrees with the
// majority on the split axes of the nodes it visits sees its nodes in the single-ray order and so
// finds the single-ray hit bit for bit. A lane that disagrees visits some of its subtrees in the
// other order: it still finds the same closest t, but between two triangles hit at exactly that t
// (a ray through a shared edge) it may keep the other one, since the first one found is kept.
#include <array>
#include <bit>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <xsimd/xsimd.hpp>

#include "accel/bvh/bvh.h"
#include "accel/bvh/bvh_node.h"
#include "core/flatten.h"
#include "core/intersect_triangle.h"
#include "core/mesh.h"
#include "core/ray.h"
#include "core/slab_test.h"
#include "simd/lanes.h"
#include "simd/mask.h"
#include "simd/packet.h"

namespace trident::bvh {

/// Subtrees that at most this many lanes of a packet still need are traced ray by ray. Measured
/// on one thread, 640x360 pixel blocks of the four built-in scenes, every threshold from 0 to the
/// width, for primary rays, diffuse bounces (closest hit) and shadow rays (any hit); speed-ups
/// over the single-ray traversal at thresholds 0 / 1 / 2, ranges over the scenes, +-5% noise:
///   4 lanes: primary 1.6-1.7 / 1.5-1.6 / 1.3-1.6, diffuse 0.8-1.6 / 0.9-1.5, shadow 1.8-1.9 / 1.6-1.9
///   8 lanes: primary 2.1-2.7 / 2.2-2.8 / 1.9-2.6, diffuse 0.9-2.1 / 1.1-2.0, shadow 2.0-2.4 / 2.2-2.5
///  16 lanes: primary 2.7-3.6 / 2.3-3.3 / 2.3-3.3, diffuse 1.0-2.5 / 1.1-2.4, shadow 2.8-3.5 / 2.6-3.2
/// Every higher threshold was slower. Embree switches much earlier (3 of 4, 5-7 of 8, 14 of 16
/// lanes) because its single-ray path tests four or eight boxes at once. Here a node costs one ray
/// about what it costs a whole packet (the packet traversal is bound by latency, not by lanes), so
/// handing lanes over pays only for a last single lane, and measurably only at 8 lanes.
constexpr int single_ray_lanes(std::size_t packet_width) { return packet_width == 8 ? 1 : 0; }

/// The flattened tree as a traversal reads it (Bvh::nodes(), leaf_triangles(), leaf_triangle_ids()).
struct TreeArrays {
    std::span<const BvhNode> nodes;
    std::span<const Triangle> triangles;
    std::span<const TriangleId> triangle_ids;
};

/// Traces `lanes` one by one through the subtree at `subtree` with trace_subtree(ray, subtree),
/// the single-ray traversal, each ray limited to its lane's closest hit so far; their hits go into
/// `hits` (any-hit queries: t becomes -inf, which ends the lane). Returns the lanes that hit.
template <bool AnyHit, class Arch, class TraceSubtree>
xsimd::batch_bool<float, Arch> trace_lanes_singly(const RayPacket<Arch>& rays, std::uint32_t lanes,
                                                  std::uint32_t subtree, HitPacket<Arch>& hits,
                                                  TraceSubtree& trace_subtree) {
    using L = Lanes<xsimd::batch<float, Arch>>;
    const auto ox = L::to_array(rays.origin.x), oy = L::to_array(rays.origin.y), oz = L::to_array(rays.origin.z);
    const auto dx = L::to_array(rays.dir.x), dy = L::to_array(rays.dir.y), dz = L::to_array(rays.dir.z);
    const auto tmin = L::to_array(rays.tmin);
    auto t = L::to_array(hits.t), u = L::to_array(hits.u), v = L::to_array(hits.v);
    std::array<std::uint32_t, L::width> ids;
    hits.triangle.store_unaligned(ids.data());
    std::array<bool, L::width> found{};
    for (; lanes != 0; lanes &= lanes - 1) {
        const int i = std::countr_zero(lanes);
        const Hit hit = trace_subtree(Ray{{ox[i], oy[i], oz[i]}, {dx[i], dy[i], dz[i]}, tmin[i], t[i]}, subtree);
        if (!hit.is_hit()) continue;
        found[i] = true;
        ids[i] = hit.triangle, u[i] = hit.u, v[i] = hit.v;
        t[i] = AnyHit ? -kInfinity : hit.t;
    }
    hits.triangle = xsimd::batch<std::uint32_t, Arch>::load_unaligned(ids.data());
    hits.t = L::from_array(t);
    hits.u = L::from_array(u);
    hits.v = L::from_array(v);
    return xsimd::batch_bool<float, Arch>::load_unaligned(found.data());
}

/// Closest hit (AnyHit false) or any hit per live lane: active and with tmin <= tmax. Hits go into
/// `hits`, whose t is each lane's limit; lanes that are not live keep what they hold. Subtrees that
/// at most `single_ray_lanes` lanes need go to trace_subtree(const Ray&, std::uint32_t node) -> Hit,
/// the single-ray traversal of that subtree. Any-hit queries end a lane at its first hit (its t
/// becomes -inf, so no box admits it again) and return the lanes that hit; closest-hit queries
/// return no lanes (their answer is `hits`). Counters count per packet: a visit_node per node box
/// the packet tests, a test_triangle per triangle it tests (and per ray in single-ray subtrees).
/// Flattened like the other structures' walks: without it, 8-lane packets took up to 1.37 times
/// as long (bench/experiments/packets.md; 16-lane packets and single rays did not change).
template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Arch, class TraceSubtree, class Counters>
TRIDENT_FLATTEN typename RayPacket<Arch>::Mask traverse_packet(const TreeArrays& tree, const RayPacket<Arch>& rays,
                                                               HitPacket<Arch>& hits, TraceSubtree&& trace_subtree,
                                                               Counters& counters, int single_ray_lanes) {
    using Float = typename RayPacket<Arch>::Float;
    using Mask = typename RayPacket<Arch>::Mask;
    using L = Lanes<Float>;
    assert(single_ray_lanes >= 0 && std::size_t(single_ray_lanes) <= RayPacket<Arch>::width);

    const Mask live = rays.active & (rays.tmin <= rays.tmax);
    Mask blocked(false);  // any-hit lanes that have hit
    if (tree.nodes.empty() || !xsimd::any(live)) return blocked;

    // Lanes entering the node's box before their limit; t_entry where they enter it. The packet
    // traversal is bound by the latency of this test, so the three axes are computed side by side
    // and combined at the end (max and min are exact, so the order does not matter; the serial
    // form made the traversal 1.4 times slower).
    //
    // The robust test takes NodeBoxTest's form (node_box_test.h, detail::clip_to_ordered_slab)
    // lane by lane: each lane's near and far plane per axis picked by RayPacket::dir_negative
    // (1 / dir < 0, the sign NodeBoxTest orders by), and a NaN distance (an origin on a plane the
    // lane runs parallel to) dropped by the max or min with the lane's interval end. It makes the
    // decisions and entry distances of the robust slab test (the equivalence tests/bvh/test_slab.cpp
    // checks), without its compare and select per plane in the chain each node waits for: 8-lane
    // packets take 0.90-0.96x the time (bench/experiments/bvh-traversal.md). The fast test is intersect_slabs bit for
    // bit; only x is clipped to [tmin, limit] there, as on y and z the serial form's max with -inf
    // and min with +inf return the other operand, NaN included.
    auto ordered_slab = [&](int axis, float lo, float hi, Float& entry, Float& exit) {
        const auto& swapped = rays.dir_negative[axis];
        entry = rays.tmin;
        exit = hits.t;
        detail::clip_to_ordered_slab(L::select(swapped, Float(hi), Float(lo)), L::select(swapped, Float(lo), Float(hi)),
                                     rays.slab.origin[axis], rays.slab.inv_dir[axis], entry, exit);
    };
    auto enter = [&](std::uint32_t node, Float& t_entry) {
        counters.visit_node();
        const Aabb& box = tree.nodes[node].bounds;
        if constexpr (Slabs == SlabTest::robust) {
            Float entry_x, exit_x, entry_y, exit_y, entry_z, exit_z;
            ordered_slab(0, box.lo.x, box.hi.x, entry_x, exit_x);
            ordered_slab(1, box.lo.y, box.hi.y, entry_y, exit_y);
            ordered_slab(2, box.lo.z, box.hi.z, entry_z, exit_z);
            t_entry = L::max(entry_x, L::max(entry_y, entry_z));
            return t_entry <= L::min(exit_x, L::min(exit_y, exit_z));
        } else {
            using detail::slab_interval;
            const auto& slab = rays.slab;
            const auto x = slab_interval<Slabs>(Float(box.lo.x), Float(box.hi.x), slab.origin.x, slab.inv_dir.x);
            const auto y = slab_interval<Slabs>(Float(box.lo.y), Float(box.hi.y), slab.origin.y, slab.inv_dir.y);
            const auto z = slab_interval<Slabs>(Float(box.lo.z), Float(box.hi.z), slab.origin.z, slab.inv_dir.z);
            t_entry = L::max(L::max(rays.tmin, x.near), L::max(y.near, z.near));
            return t_entry <= L::min(L::min(hits.t, x.far), L::min(y.far, z.far));
        }
    };
    const auto triangle_test = packet_intersector<Test>(rays);
    // Per axis, the lanes the single-ray traversal sends to the right child first (dir < 0, so
    // unlike RayPacket::dir_negative not -0).
    const Float zero(0.0f);
    const std::array<std::uint32_t, 3> negative_bits = {
        simd::mask_bits(rays.dir.x < zero), simd::mask_bits(rays.dir.y < zero), simd::mask_bits(rays.dir.z < zero)};
    // Lanes that do not enter a stacked node hold NaN, which no comparison admits.
    const Float not_entered(std::numeric_limits<float>::quiet_NaN());

    struct StackEntry {
        std::uint32_t node;
        Float t_entry;  // per lane, NaN where the lane did not enter
    };
    std::array<StackEntry, kBvhMaxDepth> stack;  // one entry per level at most, as in the single-ray traversal
    std::uint32_t stack_size = 0;

    Float t_root;
    Mask lanes = enter(0, t_root) & live;  // the lanes visiting `current`
    std::uint32_t current = 0;
    while (xsimd::any(lanes)) {
        const std::uint32_t lane_bits = simd::mask_bits(lanes);
        const int lane_count = std::popcount(lane_bits);
        const BvhNode& node = tree.nodes[current];
        if (lane_count <= single_ray_lanes) {
            const Mask hit = trace_lanes_singly<AnyHit>(rays, lane_bits, current, hits, trace_subtree);
            if constexpr (AnyHit) blocked = blocked | hit;
        } else if (node.is_leaf()) {
            const std::uint32_t end = node.first_triangle() + node.triangle_count();
            TriangleHitT<Float> h{Float(0.0f), Float(0.0f), Float(0.0f)};
            for (std::uint32_t i = node.first_triangle(); i != end; ++i) {
                counters.test_triangle();
                const Mask hit = triangle_test.intersect(tree.triangles[i], hits.t, h) & lanes;
                if (!xsimd::any(hit)) continue;
                if constexpr (AnyHit) {
                    blocked = blocked | hit;
                    hits.t = xsimd::select(hit, Float(-kInfinity), hits.t);
                    lanes = lanes & !hit;
                    if (!xsimd::any(lanes)) break;
                } else {
                    hits.record(hit, tree.triangle_ids[i], h);
                }
            }
        } else {
            // Both children are tested before the order is chosen, so their boxes load at once.
            std::uint32_t near = current + 1, far = node.right_child();
            Float t_near, t_far;
            Mask enter_near = enter(near, t_near) & lanes, enter_far = enter(far, t_far) & lanes;
            if (2 * std::popcount(negative_bits[node.split_axis()] & lane_bits) > lane_count) {
                std::swap(near, far);
                std::swap(t_near, t_far);
                std::swap(enter_near, enter_far);
            }
            if (xsimd::any(enter_near)) {
                if (xsimd::any(enter_far)) {
                    assert(stack_size < kBvhMaxDepth);
                    stack[stack_size++] = {far, xsimd::select(enter_far, t_far, not_entered)};
                }
                current = near;
                lanes = enter_near;
                continue;
            }
            if (xsimd::any(enter_far)) {
                current = far;
                lanes = enter_far;
                continue;
            }
        }
        if constexpr (AnyHit) {
            if (xsimd::all(blocked | !live)) break;
        }
        // Pop the next node some lane still needs: entered no later than its closest hit.
        lanes = Mask(false);
        while (stack_size != 0 && !xsimd::any(lanes)) {
            const StackEntry& entry = stack[--stack_size];
            current = entry.node;
            lanes = entry.t_entry <= hits.t;
        }
    }
    return blocked;
}

}  // namespace trident::bvh

namespace trident {

template <TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
void Bvh::intersect(const RayPacket<Arch>& rays, HitPacket<Arch>& hits, Counters& counters,
                    int single_ray_lanes) const {
    traverse_packet<false, Test, Slabs>(rays, hits, counters, single_ray_lanes);
}

template <TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
typename RayPacket<Arch>::Mask Bvh::occluded(const RayPacket<Arch>& rays, Counters& counters,
                                             int single_ray_lanes) const {
    HitPacket<Arch> limits(rays);
    return traverse_packet<true, Test, Slabs>(rays, limits, counters, single_ray_lanes);
}

template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
typename RayPacket<Arch>::Mask Bvh::traverse_packet(const RayPacket<Arch>& rays, HitPacket<Arch>& hits,
                                                    Counters& counters, int single_ray_lanes) const {
    if (single_ray_lanes == kDefaultSingleRayLanes) single_ray_lanes = bvh::single_ray_lanes(RayPacket<Arch>::width);
    return bvh::traverse_packet<AnyHit, Test, Slabs>(
        {nodes_, triangles_, triangle_ids_}, rays, hits,
        [&](const Ray& ray, std::uint32_t subtree) { return traverse<AnyHit, Test, Slabs>(ray, subtree, counters); },
        counters, single_ray_lanes);
}

}  // namespace trident
