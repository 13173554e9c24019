#pragma once
// Ray packet traversal of the kd-tree: one front-to-back walk for a packet of rays sharing an
// octant, each lane carrying its own interval (Wald, Slusallek, Benthin and Wagner, "Interactive
// Rendering with Coherent Ray Tracing", EG 2001, section 4), handing subtrees that only a few
// lanes still need to the single-ray walk (Benthin, Wald, Woop, Ernst and Mark, IEEE TVCG 18(9),
// 2012, as Embree does).
//
// Every decision is the single-ray traversal's (kd_traversal.h), taken lane by lane with the same
// float operations: at an interior node each lane computes its t_split and goes near only, far
// only, or both with its interval cut at t_split (over its whole interval when it lies in the
// plane: t_split is NaN), with the same 2 gamma(3) widening; a child is visited by the lanes the
// single-ray traversal would send there (even a lane whose cut interval is empty by rounding, as
// the single ray visits it too); a leaf tests its triangles in list order against its lanes with
// each lane's closest hit as the limit and keeps hits wherever they lie; a popped cell is visited
// by its lanes whose entry is not beyond their widened closest hit. Since the lanes share an
// octant, near and far are the same child for all of them, so the packet's depth-first order
// restricted to one lane is that lane's single-ray order. Each lane therefore visits the cells the
// single ray visits, in the same order, with the same limits, and finds the same hit bit for bit,
// ties between triangles at one t included. A packet whose lanes do not share an octant is split
// into octant groups traversed one after another. Any-hit lanes retire at their first hit.
#include <array>
#include <bit>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <xsimd/xsimd.hpp>

#include "accel/kdtree/kd_node.h"
#include "accel/kdtree/kd_traversal.h"
#include "accel/kdtree/kdtree.h"
#include "core/flatten.h"
#include "core/intersect_triangle.h"
#include "core/ray.h"
#include "core/slab_test.h"
#include "simd/lanes.h"
#include "simd/mask.h"
#include "simd/packet.h"

namespace trident::kd {

/// Subtrees that at most this many lanes of a packet still need are walked ray by ray. Measured
/// (single thread, primary rays at 640x360 of the four built-in scenes, best of 3-5 runs on a
/// loaded 2-core machine, so +-20%): handing off never paid at any width; at 1 or 2 lanes it was
/// within noise of 0, beyond that slower, at the full width 1.4x to 2.5x slower than 0. Kept as a
/// template parameter (tested at every setting) for machines where a single ray is cheaper.
constexpr int single_ray_lanes(std::size_t /*packet_width*/) { return 0; }

/// The live lanes of `remaining` whose direction signs are those of its lowest lane, and the
/// octant they share (bit a: negative along axis a, -0 included, as the single ray's signbit).
template <class Arch>
struct OctantGroup {
    xsimd::batch_bool<float, Arch> lanes;
    unsigned octant;

    OctantGroup(const RayPacket<Arch>& rays, const xsimd::batch_bool<float, Arch>& remaining)
        : lanes(remaining), octant(0) {
        const int first = simd::first_active_lane(remaining);
        for (int axis = 0; axis < 3; ++axis) {
            const auto& negative = rays.dir_negative[axis];
            const bool first_negative = (simd::mask_bits(negative) >> first & 1u) != 0;
            octant |= unsigned(first_negative) << axis;
            lanes = lanes & (first_negative ? negative : !negative);
        }
    }
};

/// Walks `lanes` one by one from `node`, each over its interval [t_min, t_max] there and limited
/// by its closest hit so far, with the single-ray walk; their hits go into `hits`. Returns the
/// lanes that hit.
template <KdQuery Query, TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
xsimd::batch_bool<float, Arch> walk_lanes_singly(const KdTreeView& tree, const RayPacket<Arch>& rays,
                                                 std::uint32_t lanes, std::uint32_t node,
                                                 const xsimd::batch<float, Arch>& t_min,
                                                 const xsimd::batch<float, Arch>& t_max, HitPacket<Arch>& hits,
                                                 Counters& counters) {
    using L = Lanes<xsimd::batch<float, Arch>>;
    const auto ox = L::to_array(rays.origin.x), oy = L::to_array(rays.origin.y), oz = L::to_array(rays.origin.z);
    const auto dx = L::to_array(rays.dir.x), dy = L::to_array(rays.dir.y), dz = L::to_array(rays.dir.z);
    const auto ray_tmin = L::to_array(rays.tmin), lo = L::to_array(t_min), hi = L::to_array(t_max);
    auto t = L::to_array(hits.t), u = L::to_array(hits.u), v = L::to_array(hits.v);
    std::array<std::uint32_t, L::width> ids;
    hits.triangle.store_unaligned(ids.data());
    std::array<bool, L::width> found{};
    for (; lanes != 0; lanes &= lanes - 1) {
        const int i = std::countr_zero(lanes);
        const Ray ray{{ox[i], oy[i], oz[i]}, {dx[i], dy[i], dz[i]}, ray_tmin[i], t[i]};
        Hit best{ids[i], t[i], u[i], v[i]};
        found[i] = walk_kdtree<Query, Test, Slabs>(tree, ray, SlabRay(ray.origin, ray.dir),
                                                   TriangleIntersector<Test>(ray), node, lo[i], hi[i], best, counters);
        ids[i] = best.triangle, t[i] = best.t, u[i] = best.u, v[i] = best.v;
    }
    hits.triangle = xsimd::batch<std::uint32_t, Arch>::load_unaligned(ids.data());
    hits.t = L::from_array(t);
    hits.u = L::from_array(u);
    hits.v = L::from_array(v);
    return xsimd::batch_bool<float, Arch>::load_unaligned(found.data());
}

/// Closest hit or any hit per live lane (active, tmin <= tmax): hits go into `hits`, whose t is
/// each lane's limit (the ray's tmax on entry); lanes that are not live keep what they hold.
/// Returns the lanes that hit (for any-hit queries, the answer). Subtrees that at most
/// `single_ray_lanes` lanes need go to the single-ray walk. Counters count per packet: a visit_node
/// per node the packet (or an octant group of it) visits, a test_triangle per triangle it tests;
/// single-ray walks count per ray. Flattened, as walk_kdtree(): 16-lane packets took up to 1.23
/// times as long without.
template <KdQuery Query, TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
TRIDENT_FLATTEN typename RayPacket<Arch>::Mask traverse_kdtree_packet(const KdTreeView& tree,
                                                                      const RayPacket<Arch>& rays,
                                                                      HitPacket<Arch>& hits, Counters& counters,
                                                                      int single_ray_lanes) {
    using Float = typename RayPacket<Arch>::Float;
    using Mask = typename RayPacket<Arch>::Mask;
    using detail::widened_down;
    using detail::widened_up;
    assert(single_ray_lanes >= 0 && std::size_t(single_ray_lanes) <= RayPacket<Arch>::width);

    Mask found(false);
    Mask live = rays.active & (rays.tmin <= rays.tmax);
    if (tree.nodes.empty() || !xsimd::any(live)) return found;
    Float root_min, root_max;  // each lane clipped to the scene box exactly as the single ray
    live = live & clip_to_box<Slabs>(rays.slab, Vec3T<Float>(tree.bounds.lo), Vec3T<Float>(tree.bounds.hi), rays.tmin,
                                     rays.tmax, root_min, root_max);
    const auto intersector = packet_intersector<Test>(rays);

    struct Pending {
        std::uint32_t node;
        Mask lanes;
        Float t_min, t_max;
    };
    std::array<Pending, kKdMaxDepth> stack;  // one entry per level at most, as in the single-ray walk
    for (Mask remaining = live; xsimd::any(remaining);) {
        const OctantGroup<Arch> group(rays, remaining);
        remaining = remaining & !group.lanes;
        int pending = 0;
        std::uint32_t index = 0;
        Mask lanes = group.lanes;  // the lanes visiting `index`
        Float t_min = root_min, t_max = root_max;
        // The interval's ends as the tests at each node compare them, kept beside the interval:
        // going near, the lanes that cut take widened_up(t_split), computed while the node's
        // compares run, so the chain from one node's decisions to the next node's compares holds a
        // select and not the widening's three operations as well (8-lane packets took 0.96-1.01x
        // the time). The same values as widening t_max at each node, lane by lane.
        Float t_min_widened = widened_down<Slabs>(t_min), t_max_widened = widened_up<Slabs>(t_max);
        for (;;) {
            const std::uint32_t lane_bits = simd::mask_bits(lanes);
            const KdNode node = tree.nodes[index];
            if (std::popcount(lane_bits) <= single_ray_lanes) {
                found = found | walk_lanes_singly<Query, Test, Slabs>(tree, rays, lane_bits, index, t_min, t_max, hits,
                                                                      counters);
            } else if (!node.is_leaf()) {
                counters.visit_node();
                const int axis = node.axis();
                const Float t_split = (Float(node.split()) - rays.origin[axis]) * rays.slab.inv_dir[axis];
                const bool below_first = (group.octant >> axis & 1u) == 0;
                const std::uint32_t near = below_first ? node.below_child() : node.above_child();
                const std::uint32_t far = below_first ? node.above_child() : node.below_child();
                // The single ray's if-chain, lane by lane: NaN (in the plane) fails both tests.
                const Mask near_only = t_split > t_max_widened;
                const Mask far_only = (!near_only) & (t_split < t_min_widened);
                const Mask cut = !(near_only | far_only | (t_split != t_split));  // both, at t_split
                const Mask to_near = lanes & !far_only, to_far = lanes & !near_only;
                // An empty leaf is neither visited nor pushed, as in the single-ray walk.
                const bool near_empty = below_first ? node.below_empty() : node.above_empty();
                const bool far_empty = below_first ? node.above_empty() : node.below_empty();
                if (xsimd::any(to_near)) {
                    if (!far_empty && xsimd::any(to_far))
                        stack[pending++] = {far, to_far, xsimd::select(cut, t_split, t_min), t_max};
                    if (!near_empty) {
                        index = near;
                        lanes = to_near;
                        t_max = xsimd::select(cut, t_split, t_max);
                        t_max_widened = xsimd::select(cut, widened_up<Slabs>(t_split), t_max_widened);
                        continue;
                    }
                } else if (!far_empty) {  // every lane goes far only, over its whole interval
                    index = far;
                    continue;
                }
            } else {
                counters.visit_node();
                const TriangleId* ids = tree.leaf_triangles.data() + node.triangle_offset();
                for (std::uint32_t i = 0; i < node.triangle_count(); ++i) {
                    counters.test_triangle();
                    TriangleHitT<Float> h{Float(0.0f), Float(0.0f), Float(0.0f)};
                    const Mask hit = intersector.intersect(tree.triangles[ids[i]], hits.t, h) & lanes;
                    if (!xsimd::any(hit)) continue;
                    hits.record(hit, tree.triangle_ids[ids[i]], h);
                    found = found | hit;
                    if constexpr (Query == KdQuery::any_hit) {
                        lanes = lanes & !hit;
                        if (!xsimd::any(lanes)) break;
                    }
                }
            }
            if constexpr (Query == KdQuery::any_hit) {
                if (!xsimd::any(group.lanes & !found)) break;
            }
            // The next pending cell that some lane may find a closer hit in.
            lanes = Mask(false);
            while (pending != 0 && !xsimd::any(lanes)) {
                const Pending& cell = stack[--pending];
                lanes = cell.lanes & !(cell.t_min > widened_up<Slabs>(hits.t));
                if constexpr (Query == KdQuery::any_hit) lanes = lanes & !found;
                index = cell.node;
                t_min = cell.t_min;
                t_max = cell.t_max;
            }
            if (!xsimd::any(lanes)) break;
            t_min_widened = widened_down<Slabs>(t_min);
            t_max_widened = widened_up<Slabs>(t_max);
        }
    }
    return found & live;
}

}  // namespace trident::kd

namespace trident {

template <TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
void KdTree::intersect(const RayPacket<Arch>& rays, HitPacket<Arch>& hits, Counters& counters,
                       int single_ray_lanes) const {
    if (single_ray_lanes == kDefaultSingleRayLanes) single_ray_lanes = kd::single_ray_lanes(RayPacket<Arch>::width);
    kd::traverse_kdtree_packet<KdQuery::closest_hit, Test, Slabs>(view(), rays, hits, counters, single_ray_lanes);
}

template <TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
typename RayPacket<Arch>::Mask KdTree::occluded(const RayPacket<Arch>& rays, Counters& counters,
                                                int single_ray_lanes) const {
    if (single_ray_lanes == kDefaultSingleRayLanes) single_ray_lanes = kd::single_ray_lanes(RayPacket<Arch>::width);
    HitPacket<Arch> limits(rays);
    return kd::traverse_kdtree_packet<KdQuery::any_hit, Test, Slabs>(view(), rays, limits, counters, single_ray_lanes);
}

}  // namespace trident
