#pragma once
// Packet traversal of the flattened octree: the single-ray walk of octree_traversal.h run for all
// lanes of a ray packet at once, so that every lane visits the cells it would visit alone, in the
// same order, tests the same triangles in the same order and stops where it would stop alone.
// Its hits therefore equal the single-ray hits bit for bit, ties between triangles included.
//
// How: lanes whose directions share an octant (an octant group; a mixed packet is split into
// groups traversed one after another) are mirrored alike, and in mirrored numbering every lane's
// walk through a node's children only ever adds bits (octree_walk.h), so taking the stored
// children in increasing mirrored index is front to back for all of them. Each lane's interval in
// a child follows from the parent's slab parameters (never from stored boxes): the lanes crossing
// the child for a positive length are exactly those whose walk enters it, and the rare lanes only
// touching it at an edge or corner ask the single-ray tie rule. Leaves test each triangle against
// all lanes visiting them. A lane ends where the single-ray walk ends: at a hit before its widened
// exit of the current cell, at a cell entered beyond its closest hit, or at its first hit for
// any-hit queries. A subtree entered by few enough lanes is walked by each of them alone, with the
// single-ray code.
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <xsimd/xsimd.hpp>

#include "accel/octree/octree.h"
#include "accel/octree/octree_build.h"
#include "accel/octree/octree_node.h"
#include "accel/octree/octree_packet_walk.h"
#include "accel/octree/octree_traversal.h"
#include "core/flatten.h"
#include "simd/lanes.h"
#include "simd/mask.h"
#include "simd/packet.h"

namespace trident {

/// A group of lanes sharing a mirror: for each axis, the lanes crossing it all go one way.
template <class Arch>
struct OctantGroup {
    xsimd::batch_bool<float, Arch> lanes;
    unsigned mirror;  // bit i: the group's lanes cross axis i going down
};

/// The lowest lane of `remaining` and every lane of it that crosses each axis the way the lowest
/// lane crossing that axis does (lanes parallel to an axis go with either side). Never empty when
/// `remaining` is not.
template <class Arch>
OctantGroup<Arch> next_octant_group(const PacketRootEntry<Arch>& root, xsimd::batch_bool<float, Arch> remaining) {
    OctantGroup<Arch> group{remaining, 0u};
    for (int axis = 0; axis < 3; ++axis) {
        const auto up = (!root.parallel[axis]) & !root.negative[axis];
        const std::uint32_t down_bits = simd::mask_bits(remaining & root.negative[axis]);
        const std::uint32_t crossing = down_bits | simd::mask_bits(remaining & up);
        const bool down = (down_bits & crossing & (~crossing + 1u)) != 0;
        if (down) group.mirror |= 1u << axis;
        group.lanes = group.lanes & !(down ? up : root.negative[axis]);
    }
    return group;
}

/// Subtrees (the whole tree included) entered by at most this many lanes are walked by each lane
/// alone. Measured on the built-in scenes (640x360, one thread, shared machine, +-5% noise): on
/// primary rays no threshold gains anything and 2 or more lanes lose 5-15% (the lanes' data must
/// leave the registers, and the subtrees left to few lanes are small); a lone lane walking alone
/// makes incoherent (diffuse) packets 5-15% faster and shadow-ray packets 3-10% slower. It is done
/// where a lone lane wastes the most: in 16-lane packets.
template <class Arch>
inline constexpr int kOctreeSingleRayLanes = RayPacket<Arch>::width >= 16 ? 1 : 0;

/// Walks the subtree of `node` (cell `cell`, slabs `slabs` per lane, mirrored by `mirror`) for each
/// lane of `lanes` alone with walk_octree_subtree(), recording its hits in `hits` and adding it to
/// `found` when it has one. Returns the lanes the walk finished.
template <OctreeQuery Query, TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
xsimd::batch_bool<float, Arch> walk_lanes_singly(const OctreeView& tree, const RayPacket<Arch>& rays,
                                                 const PacketRootEntry<Arch>& root, unsigned mirror,
                                                 xsimd::batch_bool<float, Arch> lanes, const OctreeNode& node,
                                                 const NodeSlabsT<xsimd::batch<float, Arch>>& slabs,
                                                 const OctreeCube& cell, HitPacket<Arch>& hits,
                                                 xsimd::batch_bool<float, Arch>& found, Counters& counters) {
    using Mask = xsimd::batch_bool<float, Arch>;
    using L = Lanes<xsimd::batch<float, Arch>>;
    const auto ox = L::to_array(rays.origin.x), oy = L::to_array(rays.origin.y), oz = L::to_array(rays.origin.z);
    const auto dx = L::to_array(rays.dir.x), dy = L::to_array(rays.dir.y), dz = L::to_array(rays.dir.z);
    const auto tmin = L::to_array(rays.tmin);
    const auto t0x = L::to_array(slabs.t0.x), t0y = L::to_array(slabs.t0.y), t0z = L::to_array(slabs.t0.z);
    const auto t1x = L::to_array(slabs.t1.x), t1y = L::to_array(slabs.t1.y), t1z = L::to_array(slabs.t1.z);
    const std::array<std::uint32_t, 3> parallel_lanes = {
        simd::mask_bits(root.parallel.x), simd::mask_bits(root.parallel.y), simd::mask_bits(root.parallel.z)};
    auto t = L::to_array(hits.t), u = L::to_array(hits.u), v = L::to_array(hits.v);
    std::array<std::uint32_t, L::width> ids;
    hits.triangle.store_unaligned(ids.data());
    std::array<bool, L::width> finished{}, hit{};
    for (std::uint32_t bits = simd::mask_bits(lanes); bits != 0; bits &= bits - 1) {
        const int i = std::countr_zero(bits);
        const Vec3f origin{ox[i], oy[i], oz[i]};
        unsigned parallel = 0;
        for (int axis = 0; axis < 3; ++axis) parallel |= ((parallel_lanes[axis] >> i) & 1u) << axis;
        // The single-ray walk does not mirror the axes a lane runs parallel to (octree_packet_walk.h).
        const OctreeWalkRay walk{origin, mirror & ~parallel, parallel};
        const TriangleIntersector<Test> intersector(origin, {dx[i], dy[i], dz[i]}, tmin[i]);
        Hit best{ids[i], t[i], u[i], v[i]};
        const NodeSlabs lane_slabs{{t0x[i], t0y[i], t0z[i]}, {t1x[i], t1y[i], t1z[i]}};
        finished[i] = walk_octree_subtree<Query, Test, Slabs>(tree, walk, intersector, tmin[i], node, lane_slabs, cell,
                                                              best, counters);
        hit[i] = best.is_hit();
        ids[i] = best.triangle, t[i] = best.t, u[i] = best.u, v[i] = best.v;
    }
    hits.triangle = xsimd::batch<std::uint32_t, Arch>::load_unaligned(ids.data());
    hits.t = L::from_array(t);
    hits.u = L::from_array(u);
    hits.v = L::from_array(v);
    found = found | Mask::load_unaligned(hit.data());
    return Mask::load_unaligned(finished.data());
}

/// Traces the lanes of `group` through `tree`, recording their hits in `hits` (whose t is each
/// lane's limit). Returns the lanes that found a hit. Closest hit or any hit, as
/// traverse_octree(). Flattened, as walk_octree_subtree() and for the same reason: packets took
/// up to 1.52 times as long with the triangle test out of line.
template <OctreeQuery Query, TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
TRIDENT_FLATTEN xsimd::batch_bool<float, Arch> traverse_octant_group(
    const OctreeView& tree, const RayPacket<Arch>& rays, const PacketRootEntry<Arch>& root,
    const TriangleIntersectorT<Test, xsimd::batch<float, Arch>>& intersector, const OctantGroup<Arch>& group,
    HitPacket<Arch>& hits, Counters& counters, int single_ray_lanes) {
    using Float = xsimd::batch<float, Arch>;
    using Mask = xsimd::batch_bool<float, Arch>;
    const unsigned mirror = group.mirror;
    Mask found(false);
    Mask done = !group.lanes;  // lanes finished, or not in the group

    struct Frame {
        NodeSlabsT<Float> slabs;
        Vec3T<Float> tm;
        Mask lanes;         // the lanes that entered the node
        unsigned children;  // the stored children still to look at, mirrored numbering
        OctreeCube cell;
        OctreeNode node;
    };
    std::array<Frame, kOctreeMaxDepth> stack;
    std::size_t top = 0;

    auto test_leaf = [&](const OctreeNode& node, const NodeSlabsT<Float>& slabs, Mask lanes) {
        const Float no_limit(-kInfinity);  // t < -inf never holds: lanes not visiting cannot hit
        Float limit = xsimd::select(lanes, hits.t, no_limit);
        const std::uint32_t end = node.triangle_offset() + node.triangle_count();
        for (std::uint32_t i = node.triangle_offset(); i < end; ++i) {
            const std::uint32_t position = tree.triangle_indices[i];
            counters.test_triangle();
            TriangleHitT<Float> h{Float(0.0f), Float(0.0f), Float(0.0f)};
            const Mask hit = intersector.intersect(tree.triangles[position], limit, h);
            if (!xsimd::any(hit)) continue;
            hits.record(hit, tree.triangle_ids[position], h);
            found = found | hit;
            if constexpr (Query == OctreeQuery::any_hit) {
                done = done | hit;
                limit = xsimd::select(hit, no_limit, limit);
                if (xsimd::all(done)) return;
            } else {
                limit = xsimd::select(hit, h.t, limit);
            }
        }
        // A lane ends here only if its hit lies before its widened exit of this cell, as alone.
        if constexpr (Query == OctreeQuery::closest_hit)
            done = done | (lanes & found & (hits.t <= widened_cell_exit<Slabs>(slabs.t_exit())));
    };
    auto visit = [&](const OctreeNode& node, const NodeSlabsT<Float>& slabs, const OctreeCube& cell, Mask lanes) {
        if (simd::active_lane_count(lanes) <= single_ray_lanes) {
            done = done | walk_lanes_singly<Query, Test, Slabs>(tree, rays, root, mirror, lanes, node, slabs, cell,
                                                                hits, found, counters);
            return;
        }
        counters.visit_node();
        if (node.is_leaf()) return test_leaf(node, slabs, lanes);
        Frame& frame = stack[top++];  // filled in place: a frame is hundreds of bytes at 16 lanes
        frame.slabs = slabs;
        frame.tm = packet_slab_midpoints(rays, root, mirror, slabs, cell);
        frame.lanes = lanes;
        frame.children = mirrored_child_mask(node.child_mask(), mirror);
        frame.cell = cell;
        frame.node = node;
    };

    visit(tree.nodes[0], root.slabs, tree.cube, group.lanes);
    while (top > 0 && !xsimd::all(done)) {
        Frame& frame = stack[top - 1];
        const Mask lanes = frame.lanes & !done;
        if (frame.children == 0 || !xsimd::any(lanes)) {
            --top;
            continue;
        }
        // Children in increasing mirrored index: front to back for every lane.
        const unsigned child = unsigned(std::countr_zero(frame.children));
        frame.children &= frame.children - 1;
        const NodeSlabsT<Float> slabs = child_slabs(child, frame.slabs, frame.tm);
        const Float t_enter = slabs.t_enter(), t_exit = slabs.t_exit();
        // The lanes whose single-ray walk enters the child: every lane crossing it for a positive
        // length, and of those only touching it, the ones the walk's ties lead in.
        Mask entering = lanes & (t_enter < t_exit);
        const Mask touching = lanes & (t_enter == t_exit);
        if (xsimd::any(touching)) entering = entering | lanes_entering_touched(touching, child, frame.slabs, frame.tm);
        entering = entering & !(t_exit < rays.tmin);
        // Front to back: a lane entering a cell beyond its closest hit is done, as alone.
        const Mask beyond = entering & (t_enter > hits.t);
        done = done | beyond;
        entering = entering & !beyond;
        const unsigned real_child = child ^ mirror;
        if (xsimd::any(entering))
            visit(tree.nodes[frame.node.child_slot(real_child)], slabs, child_cube(frame.cell, real_child), entering);
    }
    return found;
}

/// Traces the active lanes of `rays` (those with tmin <= tmax) through `tree` into `hits`, whose t
/// starts as each lane's limit; lanes not traced are left untouched. Returns the lanes that hit.
/// Subtrees entered by at most `single_ray_lanes` lanes are walked by each lane alone.
template <OctreeQuery Query, TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Arch, class Counters>
xsimd::batch_bool<float, Arch> traverse_octree_packet(const OctreeView& tree, const RayPacket<Arch>& rays,
                                                      HitPacket<Arch>& hits, Counters& counters,
                                                      int single_ray_lanes = kOctreeSingleRayLanes<Arch>) {
    using Mask = xsimd::batch_bool<float, Arch>;
    const PacketRootEntry<Arch> root(rays, tree.cube);
    const NodeSlabsT<xsimd::batch<float, Arch>>& slabs = root.slabs;
    const auto t_enter = slabs.t_enter(), t_exit = slabs.t_exit();
    // The single-ray traversal's tests at the root, lane by lane.
    Mask remaining = rays.active & (rays.tmin <= rays.tmax) & root.entered;
    remaining = remaining & !((t_enter > t_exit) | (t_exit < rays.tmin) | (t_enter > rays.tmax));
    Mask found(false);
    if (!xsimd::any(remaining)) return found;
    const auto intersector = packet_intersector<Test>(rays);
    while (xsimd::any(remaining)) {
        const OctantGroup<Arch> group = next_octant_group(root, remaining);
        remaining = remaining & !group.lanes;
        found = found | traverse_octant_group<Query, Test, Slabs>(tree, rays, root, intersector, group, hits, counters,
                                                                  single_ray_lanes);
    }
    return found;
}

template <TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
void Octree::intersect(const RayPacket<Arch>& rays, HitPacket<Arch>& hits, Counters& counters,
                       int single_ray_lanes) const {
    if (single_ray_lanes == kDefaultSingleRayLanes) single_ray_lanes = kOctreeSingleRayLanes<Arch>;
    traverse_octree_packet<OctreeQuery::closest_hit, Test, Slabs>(view(), rays, hits, counters, single_ray_lanes);
}

template <TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
typename RayPacket<Arch>::Mask Octree::occluded(const RayPacket<Arch>& rays, Counters& counters,
                                                int single_ray_lanes) const {
    if (single_ray_lanes == kDefaultSingleRayLanes) single_ray_lanes = kOctreeSingleRayLanes<Arch>;
    HitPacket<Arch> hits(rays);
    return traverse_octree_packet<OctreeQuery::any_hit, Test, Slabs>(view(), rays, hits, counters, single_ray_lanes);
}

}  // namespace trident
