#pragma once
// Ray packets through the wide BVH (instantiated in wide_bvh_packet_kernels.cpp): the whole
// packet walks the tree with one stack, each of a node's children tested against every lane (one
// lane per ray, the slab test of core/slab_test.h with the planes ordered per lane) or, for a
// packet from one origin, against the packet's frustum alone (wide_frustum.h), the children
// some lane enters visited nearest first by their nearest lane's entry, and subtrees that at most
// `single_ray_lanes` lanes still need handed to the single-ray walk (Benthin et al. 2012, as
// bvh_packet.h and Embree's hybrid traversal do). Packets whose directions spread wide go lane by
// lane from the root over a large tree, and from a node whose children their lanes mostly do not
// share over a small one (wide_packet_switch). A leaf tests each of its triangles against the
// lanes that need it.
//
// Per lane, the box test, the pruning rule (entry <= closest hit widened by kPruneSlack) and the
// tie rule (lowest id at equal t) are the single-ray walk's, so every lane ends with the single
// ray's hit bit for bit whatever order the packet visits the children in.
#include <array>
#include <bit>
#include <cstdint>
#include <optional>
#include <xsimd/xsimd.hpp>

#include "accel/bvh/packet_coherence.h"
#include "accel/bvh/wide_bvh.h"
#include "accel/bvh/wide_frustum.h"
#include "simd/mask.h"

namespace trident {

namespace bvh {

/// Per axis, the WideNode rows of the near and the far planes: one pair for a packet whose lanes
/// share an octant (picked once, as the single ray picks them), else none, and each lane picks its
/// own with selects.
struct PlaneRows {
    int near[3], far[3];

    static std::optional<PlaneRows> of_octant(int octant) {
        if (octant < 0) return std::nullopt;
        PlaneRows rows;
        for (int axis = 0; axis < 3; ++axis) {
            const bool negative = (octant >> axis & 1) != 0;
            rows.near[axis] = near_row(axis, negative);
            rows.far[axis] = far_row(axis, negative);
        }
        return rows;
    }
};

/// The lanes of `lanes` that enter child k of `node` before prune_limit(their closest hit), with
/// their entry distances (+inf elsewhere): the single ray's box test, lane by lane.
template <SlabTest Slabs, std::size_t Width, class Arch>
std::pair<typename RayPacket<Arch>::Mask, typename RayPacket<Arch>::Float> lanes_entering(
    const WideNode<Width>& node, std::size_t k, const RayPacket<Arch>& rays, const HitPacket<Arch>& hits,
    const typename RayPacket<Arch>::Mask& lanes, const std::optional<PlaneRows>& shared_rows) {
    using Float = typename RayPacket<Arch>::Float;
    Float entry = rays.tmin, exit = prune_limit(hits.t);
    for (int axis = 0; axis < 3; ++axis) {
        Float near, far;
        if (shared_rows) {
            near = Float(node.bounds[shared_rows->near[axis]][k]);
            far = Float(node.bounds[shared_rows->far[axis]][k]);
        } else {
            const Float lo(node.bounds[lower_row(axis)][k]), hi(node.bounds[upper_row(axis)][k]);
            near = xsimd::select(rays.dir_negative[axis], hi, lo);
            far = xsimd::select(rays.dir_negative[axis], lo, hi);
        }
        detail::clip_to_ordered_slab<Slabs>(near, far, rays.slab.origin[axis], rays.slab.inv_dir[axis], entry, exit);
    }
    const auto enters = lanes & (entry <= exit);
    return {enters, xsimd::select(enters, entry, Float(kInfinity))};
}

/// Triangle k of `block` against the lanes of `lanes`, recording each lane's hit by the single
/// ray's rules: the triangle limit just past the closest t, then nearer wins and at equal t the
/// lower id (closest hit), or the first hit ends the lane (any hit: its t becomes -inf, and it
/// joins `blocked`). Returns the lanes still live (any hit drops those that hit).
template <bool AnyHit, class Intersector, std::size_t BlockSize, class Arch>
typename RayPacket<Arch>::Mask test_triangle_lanes(const Intersector& intersector,
                                                   const TriangleBlock<BlockSize>& block, std::size_t k,
                                                   const RayPacket<Arch>& rays, HitPacket<Arch>& hits,
                                                   typename RayPacket<Arch>::Mask lanes,
                                                   typename RayPacket<Arch>::Mask& blocked) {
    using Float = typename RayPacket<Arch>::Float;
    using Mask = typename RayPacket<Arch>::Mask;
    // Each lane's limit: its tmax while nothing is hit, else just past the closest t
    // (triangle_limit lane by lane).
    const Float limits = xsimd::select(hits.t < rays.tmax, just_above(hits.t), hits.t);
    const Vec3T<Float> a(Float(block.a[0][k]), Float(block.a[1][k]), Float(block.a[2][k]));
    const Vec3T<Float> b(Float(block.b[0][k]), Float(block.b[1][k]), Float(block.b[2][k]));
    const Vec3T<Float> c(Float(block.c[0][k]), Float(block.c[1][k]), Float(block.c[2][k]));
    TriangleHitT<Float> h{Float(0.0f), Float(0.0f), Float(0.0f)};  // read where hit only
    const Mask hit = lanes & intersector.template intersect<ZeroAreaTriangles::left_out_by_caller>(a, b, c, limits, h);
    if (!xsimd::any(hit)) return lanes;
    if constexpr (AnyHit) {
        blocked = blocked | hit;
        hits.record(hit, block.id[k], h);
        hits.t = xsimd::select(hit, Float(-kInfinity), hits.t);
        return lanes & !hit;
    } else {
        // Nearer wins; at the same t the lower id (lane by lane: rare).
        Mask wins = hit & (h.t < hits.t);
        const Mask tied = hit & (h.t == hits.t);
        if (xsimd::any(tied)) {
            std::array<std::uint32_t, HitPacket<Arch>::width> ids;
            hits.triangle.store_unaligned(ids.data());
            std::array<bool, HitPacket<Arch>::width> lower{};
            for (std::uint32_t bits = simd::mask_bits(tied); bits != 0; bits &= bits - 1)
                lower[std::countr_zero(bits)] = block.id[k] < ids[std::countr_zero(bits)];
            wins = wins | (tied & Mask::load_unaligned(lower.data()));
        }
        hits.record(wins, block.id[k], h);
        return lanes;
    }
}

}  // namespace bvh

/// The structure's own switch, where the caller leaves it (kDefaultSingleRayLanes), with the
/// constants of packet_coherence.h: a last single lane goes alone; and a packet whose directions
/// spread beyond the cone, as diffuse rays do, walks ray by ray: over a tree of at least
/// kIncoherentAloneMinBlocks blocks every lane alone from the root (Embree's hybrid packets go
/// single as soon as one of 8 lanes, or two of 16, drops out); over a smaller tree below a node of
/// the first two levels whose entered children its lanes use less than half. Measured against
/// Embree's packets of the same rays (one thread, bench/experiments/bvh-traversal.md, "Incoherent
/// packets alone from the root"): alone from the root took six study scenes' 8-lane diffuse packets
/// from 0.74-0.80x rtcIntersect8 to 0.91-0.95x and their 16-lane ones from 0.81-0.88x to
/// 0.94-0.96x, but Teapot's, whose short walks through a tree of under 2000 blocks share most
/// nodes, from 0.93-1.02x to 0.77-0.82x, where the share of one half keeps them (the 8192 blocks
/// lie between Teapot's 1.9 thousand and the next scene's 45). The share at every level cost
/// Teapot's 8- and 16-lane diffuse packets 4% and 12% against none, where a thinned Bunny's (14
/// thousand triangles) took twice as long with none: their lanes part at the top of the tree if at
/// all, and meet again below (bench/experiments/bvh-traversal.md, "Incoherent packets over a small
/// tree"). Primary and shadow packets stay within the cone. A caller's explicit threshold (tests,
/// sweeps) means exactly that threshold and no second rule. Always inlined: called out of line, gcc
/// returned the switch through a stack slot written in parts and read back whole, whose
/// store-forwarding stall took 9% of Teapot's 8-lane primary packets on the Zen 5 host (perf;
/// bench/experiments/bvh-traversal.md).
template <class Arch>
[[gnu::always_inline]] inline bvh::PacketSwitch wide_packet_switch(const RayPacket<Arch>& rays, int single_ray_lanes,
                                                                   std::size_t tree_blocks,
                                                                   std::uint32_t lane_use_end) {
    if (single_ray_lanes != kDefaultSingleRayLanes) return {single_ray_lanes, 0.0f};
    if (bvh::directions_within_cone(rays, kCoherentCosine)) return {kWideSingleRayLanes, 0.0f};
    if (bvh::incoherent_lanes_alone_from_root(tree_blocks))
        return {int(RayPacket<Arch>::width), 0.0f, RayCoherence::incoherent};
    return {kWideSingleRayLanes, kIncoherentMinLaneUse, RayCoherence::incoherent, lane_use_end};
}

template <std::size_t Width, std::size_t BlockSize>
template <TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
void WideBvh<Width, BlockSize>::intersect(const RayPacket<Arch>& rays, HitPacket<Arch>& hits, Counters& counters,
                                          int single_ray_lanes) const {
    traverse_packet<false, Test, Slabs>(rays, hits, counters,
                                        wide_packet_switch(rays, single_ray_lanes, blocks_.size(), lane_use_end_));
}

template <std::size_t Width, std::size_t BlockSize>
template <TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
typename RayPacket<Arch>::Mask WideBvh<Width, BlockSize>::occluded(const RayPacket<Arch>& rays, Counters& counters,
                                                                   int single_ray_lanes, LastOccluder* last) const {
    HitPacket<Arch> limits(rays);
    return traverse_packet<true, Test, Slabs>(rays, limits, counters,
                                              wide_packet_switch(rays, single_ray_lanes, blocks_.size(), lane_use_end_),
                                              last != nullptr ? &last->id : nullptr);
}

template <std::size_t Width, std::size_t BlockSize>
template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
typename RayPacket<Arch>::Mask WideBvh<Width, BlockSize>::trace_singly(const RayPacket<Arch>& rays, std::uint32_t lanes,
                                                                       bvh::ChildRef from, HitPacket<Arch>& hits,
                                                                       Counters& counters, RayCoherence coherence,
                                                                       std::uint32_t* stopped_by) const {
    using Float = typename RayPacket<Arch>::Float;
    using Mask = typename RayPacket<Arch>::Mask;
    using L = Lanes<Float>;
    const auto ox = L::to_array(rays.origin.x), oy = L::to_array(rays.origin.y), oz = L::to_array(rays.origin.z);
    const auto dx = L::to_array(rays.dir.x), dy = L::to_array(rays.dir.y), dz = L::to_array(rays.dir.z);
    const auto tmin = L::to_array(rays.tmin), tmax = L::to_array(rays.tmax);
    const auto t = L::to_array(hits.t), u = L::to_array(hits.u), v = L::to_array(hits.v);
    std::array<std::uint32_t, L::width> ids;
    hits.triangle.store_unaligned(ids.data());
    // Each hit goes into its lane by selects, in registers: written into these arrays and loaded
    // back as vectors, it made the loads wait for the stores to retire (simd::lane_indices).
    const Float lane_index = simd::lane_indices<Arch>();
    Mask found(false);
    for (; lanes != 0; lanes &= lanes - 1) {
        const int i = std::countr_zero(lanes);
        const Ray ray{{ox[i], oy[i], oz[i]}, {dx[i], dy[i], dz[i]}, tmin[i], tmax[i]};
        const Hit so_far = ids[i] == kNoTriangle ? Hit{kNoTriangle, t[i]} : Hit{ids[i], t[i], u[i], v[i]};
        const Hit hit = traverse<AnyHit, Test, Slabs>(ray, from, so_far, counters, coherence, stopped_by);
        if (!hit.is_hit()) continue;
        const Mask lane = lane_index == Float(float(i));
        if constexpr (AnyHit) found = found | lane;
        hits.triangle = simd::select_index(lane, xsimd::batch<std::uint32_t, Arch>(hit.triangle), hits.triangle);
        hits.u = xsimd::select(lane, Float(hit.u), hits.u);
        hits.v = xsimd::select(lane, Float(hit.v), hits.v);
        // An any-hit lane that has hit admits no box again.
        hits.t = xsimd::select(lane, Float(AnyHit ? -kInfinity : hit.t), hits.t);
    }
    return found;
}

template <std::size_t Width, std::size_t BlockSize>
template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
TRIDENT_FLATTEN typename RayPacket<Arch>::Mask WideBvh<Width, BlockSize>::traverse_packet(
    const RayPacket<Arch>& rays, HitPacket<Arch>& hits, Counters& counters, bvh::PacketSwitch to_single_rays,
    std::uint32_t* stopped_by) const {
    using Float = typename RayPacket<Arch>::Float;
    using Mask = typename RayPacket<Arch>::Mask;
    const int single_ray_lanes = to_single_rays.single_ray_lanes;
    // Lanes of an incoherent packet that go alone walk as incoherent rays, and only a coherent
    // packet walks by the frustum alone.
    const RayCoherence coherence = to_single_rays.coherence;
    assert(single_ray_lanes >= 0 && std::size_t(single_ray_lanes) <= RayPacket<Arch>::width);

    Mask live = rays.active & (rays.tmin <= rays.tmax);
    Mask blocked(false);  // any-hit lanes that have hit
    if (nodes_.empty() || !xsimd::any(live)) return blocked;
    // Any hit: the block that stopped a lane of the packet before, tested against every lane
    // first (LastOccluder); `stopped_by` then names the last block that stops a lane here.
    if constexpr (AnyHit) {
        const std::uint32_t first_block = stopped_by != nullptr ? *stopped_by : LastOccluder::kNone;
        if (first_block != LastOccluder::kNone) {
            *stopped_by = LastOccluder::kNone;
            const auto intersector = packet_intersector<Test>(rays);
            Mask lanes = live;
            for (std::size_t k = 0; k < BlockSize && xsimd::any(lanes); ++k) {
                counters.test_triangle();
                lanes =
                    bvh::test_triangle_lanes<true>(intersector, blocks_[first_block], k, rays, hits, lanes, blocked);
            }
            if (xsimd::any(blocked)) *stopped_by = first_block;
            live = live & !blocked;
            if (!xsimd::any(live)) return blocked;
        }
    }
    // Lanes that all go alone from the root need none of the packet's bounds and precomputation.
    if (simd::active_lane_count(live) <= single_ray_lanes)
        return blocked | trace_singly<AnyHit, Test, Slabs>(rays, simd::mask_bits(live), bvh::ChildRef::node_at(0), hits,
                                                           counters, coherence, stopped_by);
    const auto intersector = packet_intersector<Test>(rays);
    const Float inf(kInfinity);
    // Packets of one octant first test a node's children against all their lanes at once
    // (wide_frustum.h), and lane by lane only the children some lane may enter.
    const std::optional<bvh::RayGroupBounds> group = bvh::RayGroupBounds::of(rays, live);
    const bvh::RayGroupBounds no_group{};  // read by reference, never copied (as `of` says why)
    const bvh::WideFrustumTest<Width, Slabs> frustum(group ? *group : no_group);
    const std::optional<bvh::PlaneRows> shared_rows = bvh::PlaneRows::of_octant(rays.octant);
    // Packets from one origin (a camera's) walk the inner nodes by the frustum alone, as Embree's
    // coherent packets do (its intersectCoherent): a child the frustum admits is entered by every
    // lane still needing a node at the frustum's entry bound, with no box test lane by lane, and
    // lanes that would not have entered it test a few triangles more (primary packets 1.03-1.15x
    // on the scenes of large triangles, the scans as before). Each lane still gets the single
    // ray's hit: with the robust slab test every hit of a lane lies in boxes its own test enters,
    // so testing more triangles finds none it would not, and the entry bound is at most each
    // lane's own, so it prunes no box the lane's test would keep. Shadow packets, whose origins
    // spread, have a loose frustum and keep the lane tests (frustum alone: 0.12-1.02x).
    const bool frustum_only =
        group && group->shares_origin() && Slabs == SlabTest::robust && coherence == RayCoherence::coherent;
    constexpr std::uint32_t kAllChildren = std::uint32_t((std::uint64_t(1) << Width) - 1);
    // The largest closest-hit distance among the live lanes, an upper bound refreshed after each
    // leaf (hits only shorten it), for the frustum's far end.
    const auto largest_t = [&] { return -simd::horizontal_min(xsimd::select(live & !blocked, -hits.t, inf)); };
    float group_t_max = group ? largest_t() : kInfinity;

    // Lanes that may still find a hit in a node entered at t_entry.
    const auto needing = [&](const Float& t_entry) { return live & !blocked & (t_entry <= bvh::prune_limit(hits.t)); };
    // The stack by field: a child per entry, its order key, and, for lane tests, a batch of entry
    // distances (+inf in lanes that do not enter). As one struct the 64-byte-aligned batch padded
    // each entry to 128 bytes. A frustum-only walk enters every lane at the key (the frustum's
    // entry bound), so it keeps no batches: the sorted insert moved a 64-byte batch for each key
    // it passed and wrote one per child entered, whose lines perf put at about 5% of Room's
    // 16-lane primary packets; without them the interiors' rows ran 1.00-1.07x as fast (A/B).
    // Any-hit lane tests keep the entering lanes as bits instead (Embree's occludedCoherent keeps
    // a mask too): an any-hit lane's limit stays its tmax until it is blocked, so a lane that
    // entered a child still needs it unless blocked since, and the pop's compare of distances
    // said nothing more. Shadow packets ran 0.97-1.01x the time with them (two A/Bs, 3 and 4
    // rounds, seven scenes, 8 and 16 lanes; bench/experiments/bvh-traversal.md).
    Float stack_t_entry[kStackSize];
    float stack_key[kStackSize];
    std::uint32_t stack_lanes[kStackSize];
    const bool lane_bits = AnyHit && !frustum_only;
    bvh::ChildRef stack_ref[kStackSize];
    std::size_t stack_size = 0;
    bvh::ChildRef current = bvh::ChildRef::node_at(0);
    Mask lanes = live;
    for (;;) {
        // Lanes that walk the current subtree alone; one call site, as the single-ray walk is
        // flattened into it.
        std::uint32_t alone = 0;
        if (simd::active_lane_count(lanes) <= single_ray_lanes) {
            alone = simd::mask_bits(lanes);
        } else if (!current.is_leaf()) {
            const Node& node = node_at(current);
            counters.visit_node();
            std::uint32_t candidates = kAllChildren;
            std::array<float, Width> entry_lo;
            if (group) candidates = frustum.may_enter(node, bvh::prune_limit(group_t_max), entry_lo);
            // The entered children go straight onto the stack, kept sorted as they come by their
            // order key (the frustum's bound where there is one, free; else the nearest lane's
            // entry), farthest first: the nearest ends on top and is popped next. Any-hit packets
            // keep no order, as the single-ray any-hit walk and Embree's occluded packets keep
            // none: any hit ends a lane's search, so the nearest child is no better a guess, and
            // sorting cost shadow packets 3-11% (bench/experiments/bvh-traversal.md).
            const std::size_t base = stack_size;
            const bool counts_lane_use = current.node_offset() < to_single_rays.lane_use_end;
            int lane_entries = 0, children_entered = 0;
            Mask entering(false);
            // Child k onto the stack with its order key and, for lane tests, its entry distances
            // *t, or for any hit its entering lanes' bits (a frustum-only walk's lanes enter at
            // the key: neither), sorted in by the key.
            const auto stack_child = [&](std::size_t k, float key, const Float* t, std::uint32_t bits) {
                std::size_t i = stack_size++;
                if constexpr (!AnyHit) {
                    for (; i > base && stack_key[i - 1] < key; --i) {
                        stack_key[i] = stack_key[i - 1];
                        if (!frustum_only) stack_t_entry[i] = stack_t_entry[i - 1];
                        stack_ref[i] = stack_ref[i - 1];
                    }
                }
                stack_key[i] = key;
                if (lane_bits)
                    stack_lanes[i] = bits;
                else if (!frustum_only)
                    stack_t_entry[i] = *t;
                stack_ref[i] = node.child[k];
                prefetch(node.child[k]);
            };
            if (frustum_only) {  // every candidate, every lane at the frustum's entry bound
                for (; candidates != 0; candidates &= candidates - 1) {
                    const std::size_t k = std::countr_zero(candidates);
                    if (node.child[k].is_empty()) break;  // the used slots come first
                    stack_child(k, entry_lo[k], nullptr, 0);
                }
            } else {
                for (; candidates != 0; candidates &= candidates - 1) {
                    const std::size_t k = std::countr_zero(candidates);
                    if (node.child[k].is_empty()) break;
                    const auto [enters, t] = bvh::lanes_entering<Slabs>(node, k, rays, hits, lanes, shared_rows);
                    if (!xsimd::any(enters)) continue;
                    if (counts_lane_use) {
                        lane_entries += simd::active_lane_count(enters);
                        ++children_entered;
                        entering = entering | enters;
                    }
                    stack_child(k, AnyHit ? 0.0f : group ? entry_lo[k] : simd::horizontal_min(t), &t,
                                AnyHit ? simd::mask_bits(enters) : 0u);
                }
            }
            assert(stack_size <= kStackSize);
            if (counts_lane_use && children_entered > 1 &&
                float(lane_entries) <
                    to_single_rays.min_lane_use * float(children_entered * simd::active_lane_count(entering))) {
                stack_size = base;  // the lanes walk the node again alone, each in its own order
                alone = simd::mask_bits(entering);
            }
        } else {
            std::uint32_t remaining = current.triangle_count();
            for (std::uint32_t b = current.first_block(); remaining != 0; ++b) {
                const Block& block = blocks_[b];
                [[maybe_unused]] const Mask was_blocked = blocked;
                for (std::uint32_t k = 0; k < BlockSize && remaining != 0; ++k, --remaining) {
                    counters.test_triangle();
                    lanes = bvh::test_triangle_lanes<AnyHit>(intersector, block, k, rays, hits, lanes, blocked);
                    if (AnyHit && !xsimd::any(lanes)) break;
                }
                if constexpr (AnyHit)
                    if (stopped_by != nullptr && xsimd::any(blocked & !was_blocked)) *stopped_by = b;
                if (AnyHit && !xsimd::any(lanes)) break;
            }
            if (group) group_t_max = largest_t();
        }
        if (alone != 0)
            blocked = blocked |
                      trace_singly<AnyHit, Test, Slabs>(rays, alone, current, hits, counters, coherence, stopped_by);
        for (;;) {  // pop the next node some lane still needs
            if (stack_size == 0) return blocked;
            --stack_size;
            lanes = lane_bits ? live & !blocked & simd::mask_from_bits<Arch>(stack_lanes[stack_size])
                              : needing(frustum_only ? Float(stack_key[stack_size]) : stack_t_entry[stack_size]);
            if (xsimd::any(lanes)) {
                current = stack_ref[stack_size];
                break;
            }
        }
    }
}

}  // namespace trident
