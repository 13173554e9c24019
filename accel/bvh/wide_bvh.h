#pragma once
// The wide BVH: a binary SAH tree (bvh.h, built for blocks: a node of one block's triangles is
// split only where the collapse gains by it, BvhOptions::split_beats_block) collapsed into nodes of
// Width children whose boxes are stored by coordinate, over leaves of triangle blocks stored by
// coordinate (wide_node.h, wide_collapse.h). One ray tests all of a node's boxes in one vector
// step (wide_box_test.h) and a block's triangles in another; Embree's BVH8 over triangle4 blocks
// is the same design.
//
// Closest hit: the children a ray enters are visited near to far (sorted by entry distance; the
// far ones stacked with it, so a popped one beyond the closest hit is skipped). Any hit: no sort,
// and the walk ends at the first hit. The closest hit is the lowest (t, triangle id) of the
// triangles the ray hits, ties at equal t going to the lower id, and boxes are pruned only beyond
// the closest t widened by kPruneSlack: the answer then does not depend on the order nodes are
// visited in, so a ray packet (wide_packet.h) gives each lane the single ray's hit bit for bit.
//
// The triangle test is the scalar one (core/intersect_triangle.h) run over a batch with one
// triangle per lane: lane for lane the same operations, so the same hits, t, u and v bits.
#include <algorithm>
#include <bit>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <span>
#include <xsimd/xsimd.hpp>

#include "accel/accel_stats.h"
#include "accel/bvh/bvh_node.h"
#include "accel/bvh/bvh_options.h"
#include "accel/bvh/packet_coherence.h"
#include "accel/bvh/wide_box_test.h"
#include "accel/bvh/wide_node.h"
#include "accel/packet_kernels.h"
#include "core/flatten.h"
#include "core/huge_page_array.h"
#include "core/intersect_triangle.h"
#include "core/mesh.h"
#include "core/prefetch.h"
#include "core/ray_coherence.h"
#include "simd/lanes.h"
#include "simd/packet.h"

namespace trident {

namespace bvh {

/// When the packet walk hands lanes to the single-ray walk: at a subtree that at most
/// `single_ray_lanes` lanes need; and at a node at a byte offset below `lane_use_end` (none by
/// default) whose entered children its lanes use less than `min_lane_use` of (children entered) x
/// (lanes entering any of them): then each of those lanes walks the node's subtree alone (Benthin
/// et al. 2012's utilization switch). The nodes being numbered breadth-first, an offset bound is a
/// bound on the level. `coherence` is the packet's: incoherent lanes walk alone as
/// incoherent rays (they prefetch what they stack), and only a coherent packet may be walked by its
/// frustum alone.
struct PacketSwitch {
    int single_ray_lanes = 1;
    float min_lane_use = 0.0f;
    RayCoherence coherence = RayCoherence::coherent;
    std::uint32_t lane_use_end = 0;
};

}  // namespace bvh

template <std::size_t Width, std::size_t BlockSize>
class WideBvh {
public:
    static constexpr std::size_t width = Width, block_size = BlockSize;
    using Node = bvh::WideNode<Width>;
    using Block = bvh::TriangleBlock<BlockSize>;
    /// A stack entry per sibling left behind: at most Width - 1 per level.
    static constexpr std::size_t kStackSize = kBvhMaxDepth * (Width - 1) + 1;

    /// The binary build (Bvh::build's, same options) and the collapse, both with oneTBB on the
    /// caller's threads; the result does not depend on their number. BvhBuilder::automatic picks
    /// the tree per mesh (builder_choice.h); options().builder then names the one built. Throws as
    /// Bvh::build does.
    static WideBvh build(const Mesh& mesh, const BvhOptions& options = {});

    /// Incoherent rays (RayCoherence) get the lines of the children they stack asked into cache.
    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Counters>
    Hit intersect(const Ray& ray, Counters& counters, RayCoherence coherence = RayCoherence::coherent) const {
        const Hit hit = traverse<false, Test, Slabs>(ray, bvh::ChildRef::node_at(0), Hit{kNoTriangle, ray.tmax},
                                                     counters, coherence);
        return hit.is_hit() ? hit : Hit{};
    }
    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Counters>
    bool occluded(const Ray& ray, Counters& counters) const {
        return traverse<true, Test, Slabs>(ray, bvh::ChildRef::node_at(0), Hit{kNoTriangle, ray.tmax}, counters)
            .is_hit();
    }

    /// occluded() for the rays of a list in turn, each a neighbour of the one before (a pixel
    /// block's shadow rays): a ray first tests the block of triangles that stopped the ray before
    /// it (`last`: LastOccluder in packet_kernels.h), and walks the tree only when that block lets
    /// it through; `last` then names the block that stopped this ray, or none. The answer is
    /// occluded()'s: a triangle the test hits lies in boxes the walk enters (robust slab test), so
    /// the walk would find a hit too.
    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Counters>
    bool occluded(const Ray& ray, Counters& counters, LastOccluder& last) const {
        std::uint32_t stopped_by = last.id;
        const bool hit = traverse<true, Test, Slabs>(ray, bvh::ChildRef::node_at(0), Hit{kNoTriangle, ray.tmax},
                                                     counters, RayCoherence::coherent, &stopped_by)
                             .is_hit();
        last.id = hit ? stopped_by : LastOccluder::kNone;
        return hit;
    }
    Hit intersect(const Ray& ray) const {
        NoCounters c;
        return intersect<TriangleTest::watertight>(ray, c);
    }
    bool occluded(const Ray& ray) const {
        NoCounters c;
        return occluded<TriangleTest::watertight>(ray, c);
    }

    /// Ray packets (wide_packet.h): per live lane the single ray's hit bit for bit, or whether
    /// anything is hit. Subtrees that at most `single_ray_lanes` lanes need (by default 1) are
    /// traced ray by ray. Any hit with `last`: the block it names is tested first, and it names
    /// the last block that stopped a lane of this packet, or none (as for single rays above).
    /// Instantiated in wide_bvh_packet_kernels.cpp: callers go through PacketKernels
    /// (accel/packet_kernels.h).
    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Arch, class Counters>
    void intersect(const RayPacket<Arch>& rays, HitPacket<Arch>& hits, Counters& counters,
                   int single_ray_lanes = kDefaultSingleRayLanes) const;
    template <TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Arch, class Counters>
    typename RayPacket<Arch>::Mask occluded(const RayPacket<Arch>& rays, Counters& counters,
                                            int single_ray_lanes = kDefaultSingleRayLanes,
                                            LastOccluder* last = nullptr) const;

    /// Whether the packet of the rays rays[index[0]], rays[index[1]], ... (traced ones, at most a
    /// packet's width) walks every lane alone from the root under the structure's own switch
    /// (wide_packet_switch): a caller that has not built the packet then traces those rays as
    /// incoherent single rays, the walks its lanes would take (ray_stream.cpp).
    bool packet_walks_lanes_alone(std::span<const Ray> rays, std::span<const std::size_t> index) const {
        return bvh::lanes_walk_alone(rays, index, blocks_.size());
    }

    /// Whether every incoherent packet walks its lanes alone from the root (a tree of at least
    /// kIncoherentAloneMinBlocks blocks, wide_packet_switch): a stream its caller calls incoherent
    /// is then traced as single rays without being cut into packets (ray_stream.h).
    bool incoherent_packets_walk_alone() const { return bvh::incoherent_lanes_alone_from_root(blocks_.size()); }

    /// The byte offset past the nodes of the first kIncoherentLaneUseLevels levels, where an
    /// incoherent packet over a small tree may part (wide_packet_switch).
    std::uint32_t lane_use_end() const { return lane_use_end_; }

    const AccelStats& stats() const { return stats_; }
    const BvhOptions& options() const { return options_; }
    std::span<const Node> nodes() const { return nodes_; }
    std::span<const Block> blocks() const { return blocks_; }
    /// The node a reference names (not a leaf's).
    const Node& node_at(bvh::ChildRef ref) const {
        assert(!ref.is_leaf());
        return *reinterpret_cast<const Node*>(reinterpret_cast<const char*>(nodes_.data()) + ref.node_offset());
    }

    /// The single-ray walk from `start` (the root: node 0) given the closest hit so far (`best`:
    /// kNoTriangle at the ray's tmax when none), which it returns improved. Counters: a
    /// visit_node per wide node whose boxes are tested, a test_triangle per real triangle of each
    /// block tested (not the padding lanes). Any hit with `stopped_by`: the block it names (unless
    /// LastOccluder::kNone) is tested before the walk, and it names the block that stopped the ray.
    template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Counters>
    TRIDENT_FLATTEN Hit traverse(const Ray& ray, bvh::ChildRef start, Hit best, Counters& counters,
                                 RayCoherence coherence = RayCoherence::coherent,
                                 std::uint32_t* stopped_by = nullptr) const;

private:
    template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
    typename RayPacket<Arch>::Mask traverse_packet(const RayPacket<Arch>& rays, HitPacket<Arch>& hits,
                                                   Counters& counters, bvh::PacketSwitch to_single_rays,
                                                   std::uint32_t* stopped_by = nullptr) const;

    /// The lanes set in `lanes`, one by one with traverse() from `from`, each continuing from its
    /// record in `hits`, with `stopped_by` as traverse() takes it; returns the any-hit lanes that
    /// hit (none for closest hit).
    template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Arch, class Counters>
    typename RayPacket<Arch>::Mask trace_singly(const RayPacket<Arch>& rays, std::uint32_t lanes, bvh::ChildRef from,
                                                HitPacket<Arch>& hits, Counters& counters, RayCoherence coherence,
                                                std::uint32_t* stopped_by = nullptr) const;

    /// Asks for a child's node, or its leaf's first block, to be brought into cache: a packet
    /// decides which children it enters well before it steps into them (Embree prefetches so), an
    /// any-hit ray for the leaves it stacks, and an incoherent closest-hit ray for every child it
    /// stacks.
    void prefetch(bvh::ChildRef child) const {
        const char* start = child.is_leaf() ? reinterpret_cast<const char*>(blocks_.data() + child.first_block())
                                            : reinterpret_cast<const char*>(&node_at(child));
        constexpr std::size_t kBytes = std::max(sizeof(Node), sizeof(Block));
        for (std::size_t offset = 0; offset < kBytes; offset += 64) prefetch_line(start + offset);
    }

    HugePageArray<Node> nodes_;
    HugePageArray<Block> blocks_;
    std::uint32_t lane_use_end_ = 0;
    BvhOptions options_;
    AccelStats stats_;
};

namespace bvh {

/// Whether a triangle hit at t with `id` beats the closest hit so far: nearer, or as near with a
/// lower id (what makes the closest hit independent of the visiting order).
inline bool beats(float t, TriangleId id, const Hit& best) { return t < best.t || (t == best.t && id < best.triangle); }

/// The float just above a hit's t, which is finite and at least the ray's tmin >= 0 (-0 counting
/// as 0): the bits of |t| plus one. That is std::nextafter(t, +inf) there, without nextafterf's
/// call (which spilled the walk's registers at every block test once a ray had a hit). For one
/// ray, and lane by lane for a packet's closest hits: the same bits either way.
inline float just_above(float t) { return std::bit_cast<float>((std::bit_cast<std::uint32_t>(t) & 0x7fffffffu) + 1u); }
template <class Arch>
xsimd::batch<float, Arch> just_above(const xsimd::batch<float, Arch>& t) {
    using UInt = xsimd::batch<std::uint32_t, Arch>;
    return xsimd::bitwise_cast<xsimd::batch<float, Arch>>(xsimd::bitwise_cast<UInt>(xsimd::abs(t)) + UInt(1u));
}

/// The limit to hand the triangle test (which accepts t < limit): the ray's tmax while nothing is
/// hit, else just past the closest t, so that a triangle at the same t can win on its id.
inline float triangle_limit(const Hit& best) { return best.is_hit() ? just_above(best.t) : best.t; }

}  // namespace bvh

template <std::size_t Width, std::size_t BlockSize>
template <bool AnyHit, TriangleTest Test, SlabTest Slabs, class Counters>
Hit WideBvh<Width, BlockSize>::traverse(const Ray& ray, bvh::ChildRef start, Hit best, Counters& counters,
                                        RayCoherence coherence, std::uint32_t* stopped_by) const {
    using BlockFloat = xsimd::make_sized_batch_t<float, BlockSize>;
    using BlockLanes = Lanes<BlockFloat>;
    if (nodes_.empty()) return best;
    const bvh::WideBoxTest<Width, Slabs> box_test(ray);
    const auto block_test = [&] {
        if constexpr (Test == TriangleTest::watertight)  // set up in scalar, then broadcast
            return TriangleIntersectorT<Test, BlockFloat>(TriangleIntersectorT<Test, float>(ray));
        else
            return TriangleIntersectorT<Test, BlockFloat>(Vec3T<BlockFloat>(ray.origin), Vec3T<BlockFloat>(ray.dir),
                                                          BlockFloat(ray.tmin));
    }();
    std::array<int, 3> ray_axes{0, 1, 2};  // the watertight test's x, y, z: rows of a block's corners
    if constexpr (Test == TriangleTest::watertight) ray_axes = block_test.ray_axes();
    // Block b against the ray: whether a triangle of it is hit, the best hit improved by it.
    const auto test_block = [&](std::uint32_t b) {
        const Block& block = blocks_[b];
        const auto load = [&](const float(&corner)[3][BlockSize], const std::array<int, 3>& rows) {
            return Vec3T<BlockFloat>(BlockFloat::load_aligned(corner[rows[0]]),
                                     BlockFloat::load_aligned(corner[rows[1]]),
                                     BlockFloat::load_aligned(corner[rows[2]]));
        };
        constexpr std::array<int, 3> kAsStored{0, 1, 2};
        constexpr auto kZeroArea = ZeroAreaTriangles::left_out_by_caller;
        const BlockFloat limit(bvh::triangle_limit(best));
        TriangleHitT<BlockFloat> h{BlockFloat(0.0f), BlockFloat(0.0f), BlockFloat(0.0f)};  // read where hit only
        const auto hit = [&] {
            if constexpr (Test == TriangleTest::watertight) {
                // The corners loaded in the ray's axes (its rows picked once a ray); the rare
                // checks in double read them again as stored.
                const auto as_stored = [&] {
                    return std::array{load(block.a, kAsStored), load(block.b, kAsStored), load(block.c, kAsStored)};
                };
                return block_test.template intersect_in_ray_axes<kZeroArea>(
                    load(block.a, ray_axes), load(block.b, ray_axes), load(block.c, ray_axes), limit, h, as_stored);
            } else {
                return block_test.template intersect<kZeroArea>(load(block.a, kAsStored), load(block.b, kAsStored),
                                                                load(block.c, kAsStored), limit, h);
            }
        }();
        std::uint32_t lanes = BlockLanes::bits(hit);
        if (lanes == 0) return false;
        const auto t = BlockLanes::to_array(h.t), u = BlockLanes::to_array(h.u), v = BlockLanes::to_array(h.v);
        for (; lanes != 0; lanes &= lanes - 1) {
            const int k = std::countr_zero(lanes);
            if (bvh::beats(t[k], block.id[k], best)) best = {block.id[k], t[k], u[k], v[k]};
        }
        return true;
    };
    if constexpr (AnyHit) {
        if (stopped_by != nullptr && *stopped_by != LastOccluder::kNone) {
            // Counted as the walk counts a block: its real triangles, not the lanes that repeat the
            // last one (TriangleBlock).
            const Block& block = blocks_[*stopped_by];
            for (std::size_t k = 0; k < BlockSize; ++k)
                if (k == 0 || block.id[k] != block.id[k - 1]) counters.test_triangle();
            if (test_block(*stopped_by)) return best;
        }
    }
    struct StackEntry {
        bvh::ChildRef ref;
        float t_entry;
    };
    StackEntry stack[kStackSize];
    std::size_t stack_size = 0;
    bvh::ChildRef current = start;
    std::array<float, Width> t_entry;
    for (;;) {
        if (!current.is_leaf()) {
            const Node& node = node_at(current);
            counters.visit_node();
            std::uint32_t entered = box_test.enter(node, ray.tmin, bvh::prune_limit(best.t), t_entry);
            if (entered != 0) {
                int first = std::countr_zero(entered);
                entered &= entered - 1;
                if (entered == 0) {
                    current = node.child[first];
                    continue;
                }
                if constexpr (AnyHit) {  // no order, no distances: any hit ends the walk
                    // With 16 children a stacked leaf's blocks are asked into cache now (shadow
                    // rays 1.02x, Buddha 1.08x); asking for stacked nodes too cost Room 22%.
                    for (; entered != 0; entered &= entered - 1) {
                        const bvh::ChildRef child = node.child[std::countr_zero(entered)];
                        stack[stack_size++] = {child, 0.0f};
                        if constexpr (Width >= 16)
                            if (child.is_leaf()) prefetch(child);
                    }
                } else {
                    // Insertion sort of the entered children, farthest first, onto the stack;
                    // the nearest becomes the next node. With 16 children, an incoherent ray asks
                    // each child it stacks into cache, so its lines arrive while the nearer
                    // subtrees are walked: diffuse rays 0.99-1.08x at 1920x1080; primary rays lost
                    // 13-17% by it at 1920x1080, their neighbours having brought those lines.
                    const bool prefetch_stacked = Width >= 16 && coherence == RayCoherence::incoherent;
                    const std::size_t base = stack_size;
                    StackEntry nearest{node.child[first], t_entry[first]};
                    for (; entered != 0; entered &= entered - 1) {
                        const int k = std::countr_zero(entered);
                        StackEntry e{node.child[k], t_entry[k]};
                        if (e.t_entry < nearest.t_entry) std::swap(e, nearest);
                        if (prefetch_stacked) prefetch(e.ref);
                        std::size_t i = stack_size++;
                        for (; i > base && stack[i - 1].t_entry < e.t_entry; --i) stack[i] = stack[i - 1];
                        stack[i] = e;
                    }
                    current = nearest.ref;
                    assert(stack_size <= kStackSize);
                    continue;
                }
                assert(stack_size <= kStackSize);
                current = node.child[first];
                continue;
            }
        } else {
            const std::uint32_t end = current.first_block() + current.template block_count<BlockSize>();
            std::uint32_t remaining = current.triangle_count();
            for (std::uint32_t b = current.first_block(); b != end; ++b) {
                for (std::uint32_t k = 0; k < std::min<std::uint32_t>(remaining, BlockSize); ++k)
                    counters.test_triangle();
                remaining -= std::min<std::uint32_t>(remaining, BlockSize);
                if (test_block(b)) {
                    if constexpr (AnyHit) {
                        if (stopped_by != nullptr) *stopped_by = b;
                        return best;
                    }
                }
            }
        }
        for (;;) {  // pop the next node that can still hold a closer hit
            if (stack_size == 0) return best;
            const StackEntry& entry = stack[--stack_size];
            // Any hit: every entry was entered below the ray's tmax, which no hit has shortened.
            if (AnyHit || entry.t_entry <= bvh::prune_limit(best.t)) {
                current = entry.ref;
                break;
            }
        }
    }
}

}  // namespace trident
