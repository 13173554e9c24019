#include "accel/kdtree/kd_build.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "accel/kdtree/clip_triangle.h"
#include "accel/kdtree/kd_event.h"
#include "accel/kdtree/radix_sort.h"
#include "accel/kdtree/sah_sweep.h"
#include "accel/kdtree/scratch_arena.h"
#include "core/morton.h"

namespace trident {

namespace {

using kd::Event;
using kd::EventType;
using kd::ScratchArena;

/// Lists at least this long are processed one axis per task.
constexpr std::size_t kParallelAxesFrom = 16384;
/// Events hold a node-local triangle index in 30 bits.
constexpr std::size_t kMaxTriangles = std::size_t(1) << 30;
/// Straddlers clipped per task (perfect splits).
constexpr std::size_t kClipGrain = 1024;

/// Where a triangle goes relative to the split plane; straddlers also get fresh events.
constexpr std::uint8_t kBelow = 1, kAbove = 2, kBoth = 3, kFreshEvents = 4;

/// One node under construction: its cell, its triangles under node-local indices, and their
/// events. All spans live in a ScratchArena.
struct NodeWork {
    Aabb cell;
    std::span<std::uint32_t> prims;     // local index -> triangle id
    std::span<std::uint8_t> flat_axes;  // local index -> bit a set when its bounds here are flat on axis a
    std::array<std::span<Event>, 3> events;

    std::size_t size() const { return prims.size(); }
};

struct Split {
    int axis = -1;
    float position = 0.0f;
    bool planars_below = false;  // the triangles lying in the plane go below (else above)
    double cost = std::numeric_limits<double>::infinity();

    bool found() const { return axis >= 0; }
};

/// A subtree in the final depth-first layout with indices relative to itself (nodes[0] is its
/// root). A node large enough to build its children as tasks is always the root of its subtree;
/// it then holds only that root, and the children are subtrees of their own.
struct Subtree {
    std::vector<KdNode> nodes;
    std::vector<TriangleId> leaf_triangles;
    std::array<std::unique_ptr<Subtree>, 2> children;  // set when the root's children were tasks
};

/// Per thread: `kept` holds children's lists until both children are built, `temp` what one split
/// needs only while it runs.
struct ThreadScratch {
    ScratchArena kept, temp;
};

const KdNode kPlaceholder = KdNode::leaf(0, 0);

std::uint8_t flat_axes_of(const Aabb& box) {
    return std::uint8_t((box.lo.x == box.hi.x ? 1 : 0) | (box.lo.y == box.hi.y ? 2 : 0) |
                        (box.lo.z == box.hi.z ? 4 : 0));
}

Aabb intersection(const Aabb& a, const Aabb& b) { return {max(a.lo, b.lo), min(a.hi, b.hi)}; }

/// Events on `axis` for each flat-axes entry: 1 where the bounds are flat, 2 elsewhere.
std::size_t event_count(std::span<const std::uint8_t> flat_axes, int axis) {
    std::size_t flat = 0;
    for (const std::uint8_t f : flat_axes) flat += (f >> axis) & 1u;
    return 2 * flat_axes.size() - flat;
}

/// Writes the events of `boxes` on `axis` in the order the radix sort needs (ends, planars,
/// starts) with local indices first_index, first_index + 1, ... `out` holds exactly as many.
template <class BoxOf>
void write_events(std::size_t count, BoxOf box_of, int axis, std::uint32_t first_index, std::size_t flat,
                  std::span<Event> out) {
    Event* ends = out.data();
    Event* planars = ends + (count - flat);
    Event* starts = planars + flat;
    for (std::size_t i = 0; i < count; ++i) {
        const Aabb& box = box_of(i);
        const auto index = std::uint32_t(first_index + i);
        if (box.lo[axis] == box.hi[axis]) {
            *planars++ = Event::make(box.lo[axis], index, EventType::planar);
        } else {
            *ends++ = Event::make(box.hi[axis], index, EventType::end);
            *starts++ = Event::make(box.lo[axis], index, EventType::start);
        }
    }
}

/// Whether a list this long is worth one task per axis: long enough, and a second thread to take
/// them (one thread runs them in order, with one axis's scratch space and no task machinery).
bool parallel_axes(std::size_t size) {
    return size >= kParallelAxesFrom && tbb::this_task_arena::max_concurrency() > 1 &&
           tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism) > 1;
}

/// Runs f(0), f(1), f(2), as parallel tasks when `parallel`.
template <class F>
void for_each_axis(bool parallel, F f) {
    if (parallel)
        tbb::parallel_invoke([&] { f(0); }, [&] { f(1); }, [&] { f(2); });
    else
        for (int axis = 0; axis < 3; ++axis) f(axis);
}

/// Per triangle of a node: per child, its index there << 2 | 1 when the child takes the triangle's
/// events from the node's lists, else 0.
using Destination = std::array<std::uint32_t, 2>;

/// Copies the events a child takes (Children: 0 below, 1 above, 2 both) renumbered to out[c],
/// advancing it; without AVX-512, out[c] may be written one past the events kept. keep[c] is 0 for
/// a child that builds no lists (its out[c] is a sink).
template <int Children>
void filter_events(std::span<const Event> events, std::span<const Destination> dest,
                   const std::array<std::uint32_t, 2>& keep, std::array<Event*, 2>& out) {
#if TRIDENT_KD_AVX512
    // Eight events at a time: their destinations gathered, each child's events compressed to the
    // front of a register and stored under a mask of as many lanes. Nothing is written past the
    // events kept.
    static_assert(sizeof(Destination) == 8 && sizeof(Event) == 8);
    const auto* const source = reinterpret_cast<const long long*>(events.data());
    const auto* const table = reinterpret_cast<const long long*>(dest.data());
    auto* below = reinterpret_cast<long long*>(out[0]);
    auto* above = reinterpret_cast<long long*>(out[1]);
    const __mmask8 keep_below = keep[0] ? 0xFF : 0, keep_above = keep[1] ? 0xFF : 0;
    // An event is position | prim_type << 32; a destination below | above << 32.
    const __m512i position_and_type = _mm512_set1_epi64(0x3FFFFFFFFll);
    const __m512i below_bit = _mm512_set1_epi64(1), above_bit = _mm512_set1_epi64(1ll << 32);
    const std::size_t n = events.size();
    for (std::size_t i = 0; i < n; i += 8) {
        const __mmask8 lanes = n - i >= 8 ? 0xFF : __mmask8((1u << (n - i)) - 1u);
        const __m512i e = _mm512_maskz_loadu_epi64(lanes, source + i);
        const __m512i d =
            _mm512_mask_i64gather_epi64(_mm512_setzero_si512(), lanes, _mm512_maskz_srli_epi64(0xFF, e, 34), table, 8);
        if constexpr (Children != 1) {
            const __mmask8 take = _mm512_mask_test_epi64_mask(keep_below, d, below_bit);
            const __m512i renumbered =
                _mm512_ternarylogic_epi64(e, _mm512_maskz_slli_epi64(0xFF, d, 32), position_and_type, 0xE4);
            _mm512_mask_storeu_epi64(below, __mmask8((1u << std::popcount(unsigned(take))) - 1u),
                                     _mm512_maskz_compress_epi64(take, renumbered));
            below += std::popcount(unsigned(take));
        }
        if constexpr (Children != 0) {
            const __mmask8 take = _mm512_mask_test_epi64_mask(keep_above, d, above_bit);
            const __m512i renumbered = _mm512_ternarylogic_epi64(e, d, position_and_type, 0xE4);
            _mm512_mask_storeu_epi64(above, __mmask8((1u << std::popcount(unsigned(take))) - 1u),
                                     _mm512_maskz_compress_epi64(take, renumbered));
            above += std::popcount(unsigned(take));
        }
    }
    out = {reinterpret_cast<Event*>(below), reinterpret_cast<Event*>(above)};
#else
    Event* below = out[0];
    Event* above = out[1];
    for (const Event& e : events) {
        const Destination& d = dest[e.prim()];
        const std::uint32_t type = e.prim_type & 3u;
        if constexpr (Children != 1) {
            *below = {e.position, (d[0] & ~3u) | type};
            below += d[0] & keep[0];
        }
        if constexpr (Children != 0) {
            *above = {e.position, (d[1] & ~3u) | type};
            above += d[1] & keep[1];
        }
    }
    out = {below, above};
#endif
}

/// What distribute() found: the straddlers, and per child its one-sided triangles and how many of
/// them are flat on each axis (one event there instead of two).
struct Distributed {
    std::size_t straddler_count = 0;
    std::array<std::uint32_t, 2> kept{0, 0};
    std::array<std::array<std::size_t, 3>, 2> flat{};
};

/// One pass over a node's triangles by side (kBelow, kAbove or kBoth): the one-sided ones appended
/// in order to their child's prims and flat axes, each triangle's Destination (its index there << 2
/// | 1 for the child that takes it, 0 for a straddler), the straddlers' local indices listed.
/// child_prims[c] and child_flat[c] hold n + 1 entries and dest n + 16 (the vector form stores
/// whole registers); entries past those kept and past n are scratch.
Distributed distribute(std::span<const std::uint8_t> side, std::span<const std::uint32_t> prims,
                       std::span<const std::uint8_t> flat_axes, std::array<std::uint32_t*, 2> child_prims,
                       std::array<std::uint8_t*, 2> child_flat, Destination* dest, std::uint32_t* straddlers) {
    Distributed out;
    const std::size_t n = prims.size();
#if TRIDENT_KD_AVX512
    // Sixteen triangles at a time: each child's prims and flat axes compressed to the front of a
    // register and stored under a mask of as many lanes (a compressing store to memory is slow on
    // some CPUs). A triangle's index in its child is its rank among the lanes going there, which
    // expanding 0, 1, 2, ... into those lanes gives. The zero-masked forms of some intrinsics,
    // with every lane set, are the plain instructions: GCC 12 warns that the plain forms read an
    // undefined vector.
    static_assert(sizeof(Destination) == 8);
    const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const __m512i first_pairs = _mm512_setr_epi32(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
    const __m512i last_pairs = _mm512_add_epi32(first_pairs, _mm512_set1_epi32(8));
    const __m512i one = _mm512_set1_epi32(1);
    auto store_first = [](auto* to, __mmask16 take, __m512i values) {
        const auto count = unsigned(std::popcount(unsigned(take)));
        const auto stored = __mmask16((1u << count) - 1u);
        if constexpr (sizeof(*to) == 4)
            _mm512_mask_storeu_epi32(to, stored, _mm512_maskz_compress_epi32(take, values));
        else
            _mm512_mask_cvtepi32_storeu_epi8(to, stored, _mm512_maskz_compress_epi32(take, values));
        return count;
    };
    auto* const dest_words = reinterpret_cast<std::uint32_t*>(dest);
    for (std::size_t i = 0; i < n; i += 16) {
        const __mmask16 lanes = n - i >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << (n - i)) - 1u);
        const __m512i s = _mm512_maskz_cvtepu8_epi32(0xFFFF, _mm_maskz_loadu_epi8(lanes, side.data() + i));
        const __m512i flat = _mm512_maskz_cvtepu8_epi32(0xFFFF, _mm_maskz_loadu_epi8(lanes, flat_axes.data() + i));
        const __m512i prim = _mm512_maskz_loadu_epi32(lanes, prims.data() + i);
        const __mmask16 goes[2] = {_mm512_cmpeq_epi32_mask(s, _mm512_set1_epi32(kBelow)),
                                   _mm512_cmpeq_epi32_mask(s, _mm512_set1_epi32(kAbove))};
        const __mmask16 straddles = _mm512_mask_cmpeq_epi32_mask(lanes, s, _mm512_set1_epi32(kBoth));
        out.straddler_count +=
            store_first(straddlers + out.straddler_count, straddles, _mm512_add_epi32(iota, _mm512_set1_epi32(int(i))));
        __m512i to[2];
        for (int c = 0; c < 2; ++c) {
            const std::uint32_t at = out.kept[c];
            const __m512i index =
                _mm512_add_epi32(_mm512_maskz_expand_epi32(goes[c], iota), _mm512_set1_epi32(int(at)));
            to[c] = _mm512_maskz_or_epi32(goes[c], _mm512_maskz_slli_epi32(0xFFFF, index, 2), one);
            store_first(child_flat[c] + at, goes[c], flat);
            out.kept[c] += store_first(child_prims[c] + at, goes[c], prim);
            for (int axis = 0; axis < 3; ++axis)
                out.flat[c][axis] += unsigned(
                    std::popcount(unsigned(_mm512_mask_test_epi32_mask(goes[c], flat, _mm512_set1_epi32(1 << axis)))));
        }
        _mm512_storeu_si512(dest_words + 2 * i, _mm512_permutex2var_epi32(to[0], first_pairs, to[1]));
        _mm512_storeu_si512(dest_words + 2 * i + 16, _mm512_permutex2var_epi32(to[0], last_pairs, to[1]));
    }
#else
    // Without branches (which side is unpredictable): each triangle is written to both children,
    // and the next triangle overwrites it where it does not stay.
    std::array<std::uint32_t, 2> at{0, 0};
    for (std::size_t i = 0; i < n; ++i) {
        const unsigned s = side[i], flat = flat_axes[i];
        straddlers[out.straddler_count] = std::uint32_t(i);
        out.straddler_count += s == kBoth;
        const std::array<std::uint32_t, 2> goes{s == kBelow, s == kAbove};
        for (int c = 0; c < 2; ++c) {
            child_prims[c][at[c]] = prims[i];
            child_flat[c][at[c]] = std::uint8_t(flat);
            dest[i][c] = (at[c] << 2 | 1u) & -goes[c];
            at[c] += goes[c];
            for (int axis = 0; axis < 3; ++axis) out.flat[c][axis] += (flat >> axis) & goes[c];
        }
    }
    out.kept = at;
#endif
    return out;
}

class SahBuilder {
public:
    SahBuilder(std::span<const Triangle> triangles, const KdTreeOptions& options)
        : file_triangles_(triangles), options_(options) {}

    KdBuildResult run() {
        KdBuildResult result;
        ThreadScratch& scratch = scratch_.local();
        const NodeWork root = make_root(scratch, result.bounds, result.triangle_ids);
        if (root.size() == 0) return result;
        max_depth_ = options_.depth_limit(root.size());
        Subtree tree;
        build_subtree(root, tree, 0, 0, scratch);
        // Reserved at their final sizes: growing these (tens of MiB) copies and faults them in again.
        std::array<std::size_t, 2> sizes{1, 0};
        count_emitted(tree, sizes);
        result.nodes.reserve(sizes[0]);
        result.leaf_triangles.reserve(sizes[1]);
        result.nodes.push_back(kPlaceholder);
        emit(tree, 0, result);
        result.triangles = std::move(triangles_);
        return result;
    }

private:
    /// The root's work, with the triangles with finite corners put in Morton order into
    /// triangles_ and bounds_ (`order` maps each position there to its file index).
    NodeWork make_root(ThreadScratch& scratch, Aabb& bounds, std::vector<TriangleId>& order) {
        std::vector<Aabb> file_bounds;
        file_bounds.reserve(file_triangles_.size());
        std::size_t finite = 0;
        for (std::size_t i = 0; i < file_triangles_.size(); ++i) {
            const Triangle& t = file_triangles_[i];
            file_bounds.push_back(t.bounds());
            if (is_finite(t.a) && is_finite(t.b) && is_finite(t.c)) {
                bounds.extend(file_bounds[i]);
                ++finite;
            }
        }
        if (finite > kMaxTriangles)
            throw std::length_error("kd-tree: " + std::to_string(finite) + " triangles exceed the " +
                                    std::to_string(kMaxTriangles) + " an event can index (30 bits)");
        NodeWork root{
            bounds, scratch.kept.allocate<std::uint32_t>(finite), scratch.kept.allocate<std::uint8_t>(finite), {}};
        const ScratchArena::Mark temp_mark = scratch.temp.mark();
        // The triangles in Morton order of their centres: the splitting passes look up
        // per-triangle data by the index of each event, and the traversals read the triangles of
        // a leaf, and both then touch memory near in the array for triangles near in space. The
        // scanned meshes' files are far from that order (bench/RESULTS.md measures what it
        // gives). The tree does not depend on this order.
        const std::span<std::uint64_t> coded = scratch.temp.allocate<std::uint64_t>(finite);
        const Vec3f extent = max(bounds.extent(), Vec3f(std::numeric_limits<float>::min()));
        const Vec3f scale{1023.0f / extent.x, 1023.0f / extent.y, 1023.0f / extent.z};
        std::size_t n = 0;
        for (std::size_t i = 0; i < file_triangles_.size(); ++i) {
            const Triangle& t = file_triangles_[i];
            if (!(is_finite(t.a) && is_finite(t.b) && is_finite(t.c))) continue;
            const Vec3f cell = (file_bounds[i].center() - bounds.lo) * scale;
            const std::uint32_t code = morton_code(std::uint32_t(cell.x), std::uint32_t(cell.y), std::uint32_t(cell.z));
            coded[n++] = std::uint64_t(code) << 32 | i;
        }
        kd::radix_sort(coded, scratch.temp.allocate<std::uint64_t>(n),
                       [](std::uint64_t c) { return std::uint32_t(c >> 32); });
        order.reserve(n);
        triangles_.reserve(n);
        bounds_.reserve(n);
        for (std::size_t j = 0; j < n; ++j) {
            const auto id = std::uint32_t(coded[j]);
            order.push_back(id);
            triangles_.push_back(file_triangles_[id]);
            bounds_.push_back(file_bounds[id]);
            root.prims[j] = std::uint32_t(j);
            root.flat_axes[j] = flat_axes_of(bounds_[j]);
        }
        std::array<std::size_t, 3> sizes{};
        for (int axis = 0; axis < 3; ++axis) {
            sizes[axis] = event_count(root.flat_axes, axis);
            root.events[axis] = scratch.kept.allocate<Event>(sizes[axis]);
        }
        const bool parallel = parallel_axes(n);
        const std::span<Event> sort_space = scratch.temp.allocate<Event>((parallel ? 3 : 1) * 2 * n);
        for_each_axis(parallel, [&](int axis) {
            const std::size_t flat = 2 * n - sizes[axis];
            write_events(
                n, [&](std::size_t i) -> const Aabb& { return bounds_[root.prims[i]]; }, axis, 0, flat,
                root.events[axis]);
            kd::sort_events(root.events[axis], sort_space.subspan(parallel ? 2 * n * std::size_t(axis) : 0));
        });
        scratch.temp.release(temp_mark);
        return root;
    }

    void build_subtree(const NodeWork& node, Subtree& out, int depth, int bad_refines, ThreadScratch& scratch) {
        out.nodes.push_back(kPlaceholder);
        build_node(node, out, 0, depth, bad_refines, scratch);
    }

    /// Builds the node into out.nodes[slot] and its descendants after it, depth first, the two
    /// children of a node side by side.
    void build_node(const NodeWork& node, Subtree& out, std::size_t slot, int depth, int bad_refines,
                    ThreadScratch& scratch) {
        Split split;
        if (node.size() > options_.leaf_triangles && depth < max_depth_) {
            if (node.size() <= options_.small_node_triangles) {
                build_small(small_node_of(node), out, slot, depth, bad_refines);
                return;
            }
            split = judged(find_split(node), node.size(), bad_refines);
        }
        if (!split.found()) {
            make_leaf(node.prims, out, slot);
            return;
        }

        const ScratchArena::Mark mark = scratch.kept.mark();
        const auto [below, above] = split_node(node, split, depth + 1 < max_depth_, scratch);
        if (node.size() >= options_.parallel_triangles) {
            // Children as tasks, into subtrees of their own; emit() lays them out as the
            // sequential branch would have. Children never outnumber their parent, so a node
            // this large is the root of its subtree.
            out.nodes[slot] = KdNode::interior(split.axis, split.position, 1);  // index set by emit()
            for (auto& child : out.children) child = std::make_unique<Subtree>();
            tbb::parallel_invoke(
                [&] { build_subtree(below, *out.children[0], depth + 1, bad_refines, scratch_.local()); },
                [&] { build_subtree(above, *out.children[1], depth + 1, bad_refines, scratch_.local()); });
        } else {
            const std::size_t first_child = out.nodes.size();
            out.nodes[slot] = KdNode::interior(split.axis, split.position, first_child);
            out.nodes.push_back(kPlaceholder);
            out.nodes.push_back(kPlaceholder);
            build_node(below, out, first_child, depth + 1, bad_refines, scratch);
            build_node(above, out, first_child + 1, depth + 1, bad_refines, scratch);
        }
        scratch.kept.release(mark);
    }

    /// pbrt: a split costing more than the leaf is allowed a few times in a row, in case the splits
    /// below it pay off; then, or when it is far worse for a small node, a leaf (no split).
    Split judged(Split split, std::size_t size, int& bad_refines) const {
        const double leaf_cost = double(options_.intersection_cost) * double(size);
        if (split.found() && split.cost > leaf_cost) {
            ++bad_refines;
            if (bad_refines >= options_.max_bad_refines || (split.cost > 4.0 * leaf_cost && size < 16)) return {};
        } else {
            bad_refines = 0;
        }
        return split;
    }

    static void make_leaf(std::span<const std::uint32_t> prims, Subtree& out, std::size_t slot) {
        const std::size_t offset = out.leaf_triangles.size();
        out.nodes[slot] = KdNode::leaf(std::uint32_t(prims.size()), offset);
        out.leaf_triangles.insert(out.leaf_triangles.end(), prims.begin(), prims.end());
        if (prims.size() > 1) std::sort(out.leaf_triangles.begin() + std::ptrdiff_t(offset), out.leaf_triangles.end());
    }

    /// Adds the nodes emit() appends for `tree` (all but its root) and its leaf-triangle entries.
    static void count_emitted(const Subtree& tree, std::array<std::size_t, 2>& sizes) {
        if (tree.children[0]) {
            sizes[0] += 2;
            for (const auto& child : tree.children) count_emitted(*child, sizes);
            return;
        }
        sizes[0] += tree.nodes.size() - 1;
        sizes[1] += tree.leaf_triangles.size();
    }

    /// Writes `tree` into `out` with its root at out.nodes[slot] and its other nodes appended, each
    /// interior node marked with which of its children are empty leaves.
    static void emit(const Subtree& tree, std::size_t slot, KdBuildResult& out) {
        if (tree.children[0]) {
            const KdNode& root = tree.nodes[0];
            const std::size_t first_child = out.nodes.size();
            out.nodes[slot] =
                KdNode::interior(root.axis(), root.split(), first_child, tree.children[0]->nodes[0].is_empty_leaf(),
                                 tree.children[1]->nodes[0].is_empty_leaf());
            out.nodes.push_back(kPlaceholder);
            out.nodes.push_back(kPlaceholder);
            emit(*tree.children[0], first_child, out);
            emit(*tree.children[1], first_child + 1, out);
            return;
        }
        const std::size_t node_base = out.nodes.size() - 1;  // tree.nodes[j], j >= 1, lands at node_base + j
        const std::size_t triangle_base = out.leaf_triangles.size();
        auto moved = [&](const KdNode& n) {
            return n.is_leaf() ? KdNode::leaf(n.triangle_count(), triangle_base + n.triangle_offset())
                               : KdNode::interior(n.axis(), n.split(), node_base + n.below_child(),
                                                  tree.nodes[n.below_child()].is_empty_leaf(),
                                                  tree.nodes[n.above_child()].is_empty_leaf());
        };
        out.nodes[slot] = moved(tree.nodes[0]);
        for (std::size_t j = 1; j < tree.nodes.size(); ++j) out.nodes.push_back(moved(tree.nodes[j]));
        out.leaf_triangles.insert(out.leaf_triangles.end(), tree.leaf_triangles.begin(), tree.leaf_triangles.end());
    }

    // ---- Choosing the plane (Wald and Havran, section 4.2) ---------------------------------------

    Split find_split(const NodeWork& node) const {
        std::array<Split, 3> best;
        for_each_axis(parallel_axes(node.size()), [&](int axis) { best[axis] = sweep(node, axis); });
        Split out;
        for (const Split& s : best)
            if (s.cost < out.cost) out = s;  // ties to the lower axis
        return out;
    }

    /// What the SAH of one axis needs of a node's cell, and the cell's half surface area (not
    /// positive for a cell reduced to a segment or a point, which no plane can split).
    struct AxisSetup {
        kd::SweepSetup sweep;
        double half_area;
    };
    AxisSetup axis_setup(const Aabb& cell, int axis, std::size_t size) const {
        const Vec3f extent = cell.extent();
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        // Half surface areas: the children's faces across `axis` are fixed, their sides scale.
        const double across = double(extent[u]) * double(extent[v]);
        const double side = double(extent[u]) + double(extent[v]);
        const float lo = cell.lo[axis], hi = cell.hi[axis];
        return {{std::int64_t(size), across - double(lo) * side, across + double(hi) * side, side, lo, hi,
                 1.0 - double(options_.empty_bonus)},
                across + double(extent[axis]) * side};
    }
    double split_cost(double weighted, double half_area) const {
        return double(options_.traversal_cost) + double(options_.intersection_cost) * weighted / half_area;
    }

    /// The cheapest plane on one axis (sah_sweep.h).
    Split sweep(const NodeWork& node, int axis) const {
        const AxisSetup setup = axis_setup(node.cell, axis, node.size());
        if (!(setup.half_area > 0.0)) return {};
        const kd::SweepBest best = kd::sweep_events(node.events[axis], setup.sweep);
        if (!best.found()) return {};
        return {axis, node.events[axis][best.tag >> 1].position, (best.tag & 1u) != 0,
                split_cost(best.weighted(), setup.half_area)};
    }

    // ---- Small nodes -----------------------------------------------------------------------------

    /// A node of at most options_.small_node_triangles triangles is built, with its whole subtree,
    /// from its triangles' boxes in fixed arrays instead of event lists: SAH by counting
    /// (kd::count_planes), the split by comparing box ends with the plane. The event lists' upkeep
    /// (the classification, the renumbering, the filtered copies, the scratch allocations) costs a
    /// node of a few triangles far more than its plane search; these nodes are most of the tree.
    /// The boxes are the ones its events describe, so the tree is the one the event lists give,
    /// node for node. Up to 8 triangles, because their 16 box ends are one AVX-512 vector; 16
    /// (two vectors) built Gallery slower (bench/RESULTS.md).
    static constexpr std::size_t kSmallNode = KdTreeOptions::kMaxSmallNodeTriangles;

    struct SmallNode {
        Aabb cell;
        std::size_t count = 0;
        std::array<std::uint32_t, kSmallNode> prims;  // local index -> triangle
        std::array<kd::BoxEnds<kSmallNode>, 3> axes;  // per axis, each triangle's box ends here

        std::span<const std::uint32_t> triangles() const { return {prims.data(), count}; }
        /// Appends a triangle with its box ends (`lo` and `hi` per axis).
        void add(std::uint32_t prim, const float (&lo)[3], const float (&hi)[3]) {
            prims[count] = prim;
            for (int axis = 0; axis < 3; ++axis) {
                axes[axis].lo[count] = lo[axis];
                axes[axis].hi[count] = hi[axis];
            }
            ++count;
        }
        /// Pads the arrays past `count` with ends no plane counts.
        void pad() {
            for (auto& ends : axes)
                for (std::size_t j = count; j < kSmallNode; ++j) {
                    ends.lo[j] = kInfinity;
                    ends.hi[j] = -kInfinity;
                }
        }
    };

    /// The boxes a node's events describe: a start is a box's lower end, an end its upper end, a
    /// planar event both.
    static SmallNode small_node_of(const NodeWork& node) {
        SmallNode small;
        small.cell = node.cell;
        small.count = node.size();
        std::copy(node.prims.begin(), node.prims.end(), small.prims.begin());
        small.pad();
        for (int axis = 0; axis < 3; ++axis) {
            kd::BoxEnds<kSmallNode>& ends = small.axes[axis];
            for (const Event& e : node.events[axis]) {
                if (e.type() != EventType::end) ends.lo[e.prim()] = e.position;
                if (e.type() != EventType::start) ends.hi[e.prim()] = e.position;
            }
        }
        return small;
    }

    void build_small(const SmallNode& node, Subtree& out, std::size_t slot, int depth, int bad_refines) const {
        Split split;
        if (node.count > options_.leaf_triangles && depth < max_depth_)
            split = judged(find_small_split(node), node.count, bad_refines);
        if (!split.found()) {
            make_leaf(node.triangles(), out, slot);
            return;
        }
        SmallNode below, above;
        split_small(node, split, below, above);
        const std::size_t first_child = out.nodes.size();
        out.nodes[slot] = KdNode::interior(split.axis, split.position, first_child);
        out.nodes.push_back(kPlaceholder);
        out.nodes.push_back(kPlaceholder);
        build_small(below, out, first_child, depth + 1, bad_refines);
        build_small(above, out, first_child + 1, depth + 1, bad_refines);
    }

    /// find_split's plane for the node's events, from its boxes.
    Split find_small_split(const SmallNode& node) const {
        Split out;
        for (int axis = 0; axis < 3; ++axis) {
            const AxisSetup setup = axis_setup(node.cell, axis, node.count);
            if (!(setup.half_area > 0.0)) continue;
            const kd::CountedPlane plane = kd::count_planes(node.axes[axis], node.count, setup.sweep);
            if (!plane.found()) continue;
            const double cost = split_cost(plane.weighted(), setup.half_area);
            if (cost < out.cost) out = {axis, plane.position, plane.planars_below, cost};  // ties to the lower axis
        }
        return out;
    }

    /// split_node's children, from the boxes: a box ending on or before the plane goes below, one
    /// starting on or after it above, a flat one in it to the side the split names, and a box
    /// across it (a straddler) to both, clamped to each child's cell (clipped, with perfect splits).
    void split_small(const SmallNode& node, const Split& split, SmallNode& below, SmallNode& above) const {
        const int k = split.axis;
        const float p = split.position;
        below.cell = above.cell = node.cell;
        below.cell.hi[k] = p;
        above.cell.lo[k] = p;
        std::array<std::uint32_t, kSmallNode> straddlers;
        std::size_t straddler_count = 0;
        auto ends_of = [&](std::size_t i, float(&lo)[3], float(&hi)[3]) {
            for (int axis = 0; axis < 3; ++axis) {
                lo[axis] = node.axes[axis].lo[i];
                hi[axis] = node.axes[axis].hi[i];
            }
        };
        for (std::size_t i = 0; i < node.count; ++i) {
            const float lo_k = node.axes[k].lo[i], hi_k = node.axes[k].hi[i];
            const bool flat = lo_k == hi_k;
            const bool goes_below = flat ? lo_k < p || (lo_k == p && split.planars_below) : hi_k <= p;
            const bool goes_above = flat ? lo_k > p || (lo_k == p && !split.planars_below) : lo_k >= p;
            if (!goes_below && !goes_above) {
                straddlers[straddler_count++] = std::uint32_t(i);
                continue;
            }
            float lo[3], hi[3];
            ends_of(i, lo, hi);
            (goes_below ? below : above).add(node.prims[i], lo, hi);
        }
        for (std::size_t j = 0; j < straddler_count; ++j) {
            const std::uint32_t i = straddlers[j];
            if (!options_.perfect_splits) {
                float lo[3], hi[3];
                ends_of(i, lo, hi);
                const float hi_k = hi[k];
                hi[k] = p;
                below.add(node.prims[i], lo, hi);
                hi[k] = hi_k;
                lo[k] = p;
                above.add(node.prims[i], lo, hi);
                continue;
            }
            // As split_node clips them: both empty only through rounding, for a triangle touching
            // the plane, and then the clamped boxes go to both sides.
            const std::uint32_t id = node.prims[i];
            std::array<Aabb, 2> boxes{intersection(bounds_[id], below.cell), intersection(bounds_[id], above.cell)};
            const auto clipped_below = kd::clipped_triangle_bounds(triangles_[id], below.cell);
            const auto clipped_above = kd::clipped_triangle_bounds(triangles_[id], above.cell);
            const bool both = !clipped_below && !clipped_above;
            if (clipped_below) boxes[0] = *clipped_below;
            if (clipped_above) boxes[1] = *clipped_above;
            for (int c = 0; c < 2; ++c) {
                if (!both && !(c == 0 ? clipped_below : clipped_above)) continue;
                const float lo[3] = {boxes[c].lo.x, boxes[c].lo.y, boxes[c].lo.z};
                const float hi[3] = {boxes[c].hi.x, boxes[c].hi.y, boxes[c].hi.z};
                (c == 0 ? below : above).add(id, lo, hi);
            }
        }
        below.pad();
        above.pad();
    }

    // ---- Splitting the node's lists (Wald and Havran, sections 4.3 and 4.4) ----------------------

    /// Splits the node's triangles and, for a child that may split again (children_may_split and
    /// more than leaf_triangles triangles), its event lists; a child that is a leaf at once gets
    /// its triangles only.
    std::array<NodeWork, 2> split_node(const NodeWork& node, const Split& split, bool children_may_split,
                                       ThreadScratch& scratch) const {
        const std::size_t n = node.size();
        const int k = split.axis;
        const float p = split.position;
        const bool perfect = options_.perfect_splits;
        const ScratchArena::Mark temp_mark = scratch.temp.mark();

        // Classify: one pass over the split axis's events, in three runs split at the plane's
        // group: before it (events below the plane and ends on it), its planars, after it (starts
        // on it and events above). A triangle that ends in the first run lies below (its start
        // comes earlier and changes nothing), one that starts in the last lies above (its end
        // comes later and changes nothing), a planar one goes where its run says, and one that
        // does neither straddles. Each event stores its side, or writes to a sink past the
        // triangles when it says nothing: stores alone, no read of the side before.
        const std::span<const Event> split_events = node.events[k];
        const auto first_planar = std::size_t(std::lower_bound(split_events.begin(), split_events.end(),
                                                               Event::make(p, 0, EventType::planar), kd::event_before) -
                                              split_events.begin());
        const auto first_start =
            std::size_t(std::lower_bound(split_events.begin() + std::ptrdiff_t(first_planar), split_events.end(),
                                         Event::make(p, 0, EventType::start), kd::event_before) -
                        split_events.begin());
        const std::span<std::uint8_t> side = scratch.temp.allocate<std::uint8_t>(n + 1);
        std::fill(side.begin(), side.end(), kBoth);
        {
            // Local copies: the byte stores below may alias anything whose address is taken, and
            // the loop bounds would be read again from memory at every step.
            std::uint8_t* const sides = side.data();
            const Event* const events = split_events.data();
            const std::size_t planars_from = first_planar, starts_from = first_start, end = split_events.size();
            const auto sink = std::uint32_t(n);
            // The event's triangle, or the sink for an event of the silent type, without a branch:
            // the types come mixed, and a branch on them is mispredicted.
            auto target = [sink](const Event& e, EventType silent) {
                const std::uint32_t prim = e.prim();
                const std::uint32_t is_silent = -std::uint32_t((e.prim_type & 3u) == std::uint32_t(silent));
                return prim ^ ((prim ^ sink) & is_silent);
            };
            for (std::size_t i = 0; i < planars_from; ++i) sides[target(events[i], EventType::start)] = kBelow;
            const std::uint8_t in_plane = split.planars_below ? kBelow : kAbove;
            for (std::size_t i = planars_from; i < starts_from; ++i) sides[events[i].prim()] = in_plane;
            for (std::size_t i = starts_from; i < end; ++i) sides[target(events[i], EventType::end)] = kAbove;
        }

        // One pass over the triangles: the straddlers listed, the one-sided triangles given to
        // their child (with their new local indices in `dest`, the straddlers' set further down).
        // Each child's arrays are allocated for all n triangles, since its size is known only
        // after the pass.
        std::array<std::span<std::uint32_t>, 2> child_prims;
        std::array<std::span<std::uint8_t>, 2> child_flat;
        for (int c = 0; c < 2; ++c) {
            child_prims[c] = scratch.kept.allocate<std::uint32_t>(n + 1);
            child_flat[c] = scratch.kept.allocate<std::uint8_t>(n + 1);
        }
        const std::span<Destination> dest = scratch.temp.allocate<Destination>(n + 16);
        const std::span<std::uint32_t> all_straddlers = scratch.temp.allocate<std::uint32_t>(n);
        const Distributed one_sided =
            distribute(side.first(n), node.prims, node.flat_axes, {child_prims[0].data(), child_prims[1].data()},
                       {child_flat[0].data(), child_flat[1].data()}, dest.data(), all_straddlers.data());
        const std::size_t straddler_count = one_sided.straddler_count;
        const std::array<std::uint32_t, 2>& kept_count = one_sided.kept;
        const std::span<const std::uint32_t> straddlers = all_straddlers.first(straddler_count);

        // The straddlers' bounds in each child. Without perfect splits they are the node's bounds
        // clamped to the child's cell: unchanged off the split axis, so their events there are the
        // node's, and on the split axis the plane replaces the end (below) or the start (above).
        // Perfect splits clip them (which may show that a triangle misses one child) and give
        // them fresh events on every axis.
        std::array<Aabb, 2> cells{node.cell, node.cell};
        cells[0].hi[k] = p;
        cells[1].lo[k] = p;
        std::span<Aabb> straddler_bounds;
        std::array<std::size_t, 2> fresh_count{0, 0};
        std::array<std::array<std::size_t, 3>, 2> flat_fresh{};
        if (perfect) {
            straddler_bounds = scratch.temp.allocate<Aabb>(2 * straddler_count);
            auto bound_straddlers = [&](std::size_t begin, std::size_t end) {
                for (std::size_t j = begin; j < end; ++j) {
                    const std::uint32_t i = straddlers[j];
                    const TriangleId id = node.prims[i];
                    for (int c = 0; c < 2; ++c) straddler_bounds[2 * j + c] = intersection(bounds_[id], cells[c]);
                    const auto below = kd::clipped_triangle_bounds(triangles_[id], cells[0]);
                    const auto above = kd::clipped_triangle_bounds(triangles_[id], cells[1]);
                    // Both empty only through rounding, for a triangle touching the plane: keep
                    // the clamped boxes on both sides.
                    if (below || above) side[i] = std::uint8_t((below ? kBelow : 0) | (above ? kAbove : 0));
                    if (below) straddler_bounds[2 * j] = *below;
                    if (above) straddler_bounds[2 * j + 1] = *above;
                    side[i] |= kFreshEvents;
                }
            };
            if (straddler_count >= 2 * kClipGrain)
                tbb::parallel_for(
                    tbb::blocked_range<std::size_t>(0, straddler_count, kClipGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) { bound_straddlers(r.begin(), r.end()); });
            else
                bound_straddlers(0, straddler_count);
            for (std::size_t j = 0; j < straddler_count; ++j)
                for (int c = 0; c < 2; ++c) {
                    if (!(side[straddlers[j]] & (1u << c))) continue;
                    ++fresh_count[c];
                    const Aabb& box = straddler_bounds[2 * j + std::size_t(c)];
                    for (int axis = 0; axis < 3; ++axis) flat_fresh[c][axis] += box.lo[axis] == box.hi[axis];
                }
        } else {
            fresh_count = {straddler_count, straddler_count};
            for (int axis = 0; axis < 3; ++axis) {
                // Flat straddlers: all flat triangles (one event each) less the one-sided ones.
                const std::size_t flat_all = 2 * n - node.events[axis].size();
                flat_fresh[0][axis] = flat_fresh[1][axis] =
                    flat_all - one_sided.flat[0][axis] - one_sided.flat[1][axis];
            }
        }

        // Sizes: triangles per child, and per child and axis all events and the fresh ones (those
        // sorted and merged in: perfect splits only).
        std::array<bool, 2> lists{};
        std::array<std::array<std::size_t, 3>, 2> fresh_size{}, total{};
        std::size_t fresh_total = 0, sort_size = 0;
        std::array<NodeWork, 2> child;
        for (int c = 0; c < 2; ++c) {
            const std::size_t size = kept_count[c] + fresh_count[c];
            lists[c] = children_may_split && size > options_.leaf_triangles;
            child[c].cell = cells[c];
            child[c].prims = child_prims[c].first(size);
            child[c].flat_axes = child_flat[c].first(size);
            if (!lists[c]) continue;
            for (int axis = 0; axis < 3; ++axis) {
                total[c][axis] = 2 * size - one_sided.flat[c][axis] - flat_fresh[c][axis];
                if (!perfect) continue;
                fresh_size[c][axis] = 2 * fresh_count[c] - flat_fresh[c][axis];
                fresh_total += fresh_size[c][axis];
                sort_size = std::max(sort_size, fresh_size[c][axis]);
            }
            // One slot of slack after each list: the branch-free filter below may write one past.
            const std::span<Event> all = scratch.kept.allocate<Event>(total[c][0] + total[c][1] + total[c][2] + 3);
            for (std::size_t axis = 0, at = 0; axis < 3; at += total[c][axis++] + 1)
                child[c].events[axis] = all.subspan(at, total[c][axis]);
        }

        // The straddlers follow the one-sided triangles in each child that takes them. dest[i][c]
        // is the index in child c << 2 | 1 when that child takes the triangle's events from the
        // node's lists, 0 when not (the other side, or fresh events).
        std::array<std::uint32_t, 2> next = kept_count;
        for (std::size_t j = 0; j < straddler_count; ++j) {
            const std::uint32_t i = straddlers[j];
            for (unsigned c = 0; c < 2; ++c) {
                if (!(side[i] & (1u << c))) continue;
                const std::uint32_t index = next[c]++;
                child[c].prims[index] = node.prims[i];
                if (perfect) {
                    child[c].flat_axes[index] = flat_axes_of(straddler_bounds[2 * j + c]);
                } else {
                    child[c].flat_axes[index] = node.flat_axes[i];
                    dest[i][c] = index << 2 | 1u;
                }
            }
        }

        // Per axis and child: the events taken from the node's list, filtered in order. On the
        // split axis, the events below the plane go only below and those above only above, and
        // without perfect splits the straddlers' new ends and starts at the plane go in between;
        // with perfect splits, the fresh events are written, sorted and merged in front.
        const std::span<Event> fresh_space = scratch.temp.allocate<Event>(fresh_total);
        const bool parallel = parallel_axes(n);
        const std::span<Event> sort_space = scratch.temp.allocate<Event>((parallel ? 3 : 1) * sort_size);
        const std::array<std::uint32_t, 2> keep{lists[0], lists[1]};
        for_each_axis(parallel, [&](int axis) {
            Event sink[2];  // where a child without lists gets its events
            std::array<Event*, 2> out{};
            for (int c = 0; c < 2; ++c) out[c] = lists[c] ? child[c].events[axis].data() + fresh_size[c][axis] : sink;
            const std::span<const Event> events = node.events[axis];
            if (axis != k) {
                filter_events<2>(events, dest, keep, out);
            } else {
                // Below: events before the plane, ends on it; [straddlers' ends]; planars on it.
                filter_events<0>(events.first(first_planar), dest, keep, out);
                if (!perfect && lists[0])
                    for (std::size_t j = 0; j < straddler_count; ++j)
                        *out[0]++ = Event::make(p, std::uint32_t(kept_count[0] + j), EventType::end);
                filter_events<0>(events.subspan(first_planar, first_start - first_planar), dest, keep, out);
                // Above: planars on the plane; [straddlers' starts]; starts on it, events after it.
                filter_events<1>(events.subspan(first_planar, first_start - first_planar), dest, keep, out);
                if (!perfect && lists[1])
                    for (std::size_t j = 0; j < straddler_count; ++j)
                        *out[1]++ = Event::make(p, std::uint32_t(kept_count[1] + j), EventType::start);
                filter_events<1>(events.subspan(first_start), dest, keep, out);
            }
            if (!perfect || straddler_count == 0) return;
            const std::span<Event> sort_scratch = sort_space.subspan((parallel ? axis : 0) * sort_size, sort_size);
            std::size_t fresh_at = 0;
            for (int c = 0; c < 2; ++c) {
                for (int a = 0; a < axis; ++a) fresh_at += fresh_size[c][a];
                const std::span<Event> fresh = fresh_space.subspan(fresh_at, fresh_size[c][axis]);
                for (int a = axis; a < 3; ++a) fresh_at += fresh_size[c][a];
                if (fresh.empty()) continue;
                // The straddlers this child keeps, in the order their indices were given.
                std::size_t j = 0;
                auto box_of = [&](std::size_t) -> const Aabb& {
                    while (!(side[straddlers[j]] & (1u << c))) ++j;
                    return straddler_bounds[2 * j++ + std::size_t(c)];
                };
                write_events(fresh_count[c], box_of, axis, std::uint32_t(kept_count[c]), flat_fresh[c][axis], fresh);
                kd::sort_events(fresh, sort_scratch);
                kd::merge_into_tail(fresh, child[c].events[axis]);
            }
        });
        scratch.temp.release(temp_mark);
        return child;
    }

    std::span<const Triangle> file_triangles_;
    std::vector<Triangle> triangles_;  // those with finite corners, in Morton order
    const KdTreeOptions& options_;
    std::vector<Aabb> bounds_;  // per triangle of triangles_
    int max_depth_ = 0;
    tbb::enumerable_thread_specific<ThreadScratch> scratch_;
};

}  // namespace

KdBuildResult build_kdtree(std::span<const Triangle> triangles, const KdTreeOptions& options) {
    return SahBuilder(triangles, options).run();
}

}  // namespace trident
