#pragma once
// The kd-tree builder of kd_build.h, in four parts that share this class: the driver (the root's
// events, the recursion, the subtrees' layout: kd_build.cpp), the event sweep that chooses a
// node's plane (kd_event_sweep.cpp), the classification that splits a node's event lists between
// its children (kd_classify.cpp), and the small-node search that builds the last levels from boxes
// instead of events (kd_small_node.cpp).
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "accel/kdtree/kd_build.h"
#include "accel/kdtree/kd_event.h"
#include "accel/kdtree/sah_sweep.h"
#include "accel/kdtree/scratch_arena.h"

namespace trident::kd {

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

inline const KdNode kPlaceholder = KdNode::leaf(0, 0);

/// A node of at most options_.small_node_triangles triangles is built, with its whole subtree,
/// from its triangles' boxes in fixed arrays instead of event lists: SAH by counting
/// (kd::count_planes), the split by comparing box ends with the plane. The event lists' upkeep
/// (the classification, the renumbering, the filtered copies, the scratch allocations) costs a
/// node of a few triangles far more than its plane search; these nodes are most of the tree.
/// The boxes are the ones its events describe, so the tree is the one the event lists give,
/// node for node. Up to 8 triangles, because their 16 box ends are one AVX-512 vector; 16
/// (two vectors) built Gallery slower (bench/experiments/kdtree.md).
inline constexpr std::size_t kSmallNode = KdTreeOptions::kMaxSmallNodeTriangles;

struct SmallNode {
    Aabb cell;
    std::size_t count = 0;
    std::array<std::uint32_t, kSmallNode> prims;  // local index -> triangle
    std::array<BoxEnds<kSmallNode>, 3> axes;      // per axis, each triangle's box ends here

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

inline std::uint8_t flat_axes_of(const Aabb& box) {
    return std::uint8_t((box.lo.x == box.hi.x ? 1 : 0) | (box.lo.y == box.hi.y ? 2 : 0) |
                        (box.lo.z == box.hi.z ? 4 : 0));
}

inline Aabb intersection(const Aabb& a, const Aabb& b) { return {max(a.lo, b.lo), min(a.hi, b.hi)}; }

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

/// Lists at least this long are processed one axis per task.
inline constexpr std::size_t kParallelAxesFrom = 16384;

/// Whether a list this long is worth one task per axis: long enough, and a second thread to take
/// them (one thread runs them in order, with one axis's scratch space and no task machinery).
inline bool parallel_axes(std::size_t size) {
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

class SahBuilder {
public:
    SahBuilder(std::span<const Triangle> triangles, const KdTreeOptions& options)
        : file_triangles_(triangles), options_(options) {}

    KdBuildResult run();

private:
    // ---- The driver (kd_build.cpp) ---------------------------------------------------------------

    /// The root's work, with the triangles with finite corners put in Morton order into
    /// triangles_ and bounds_ (`order` maps each position there to its file index).
    NodeWork make_root(ThreadScratch& scratch, Aabb& bounds, std::vector<TriangleId>& order);
    void build_subtree(const NodeWork& node, Subtree& out, int depth, int bad_refines, ThreadScratch& scratch);
    /// Builds the node into out.nodes[slot] and its descendants after it, depth first, the two
    /// children of a node side by side.
    void build_node(const NodeWork& node, Subtree& out, std::size_t slot, int depth, int bad_refines,
                    ThreadScratch& scratch);
    /// pbrt: a split costing more than the leaf is allowed a few times in a row, in case the splits
    /// below it pay off; then, or when it is far worse for a small node, a leaf (no split).
    Split judged(Split split, std::size_t size, int& bad_refines) const;
    static void make_leaf(std::span<const std::uint32_t> prims, Subtree& out, std::size_t slot);
    /// Adds the nodes emit() appends for `tree` (all but its root) and its leaf-triangle entries.
    static void count_emitted(const Subtree& tree, std::array<std::size_t, 2>& sizes);
    /// Writes `tree` into `out` with its root at out.nodes[slot] and its other nodes appended, each
    /// interior node marked with which of its children are empty leaves.
    static void emit(const Subtree& tree, std::size_t slot, KdBuildResult& out);

    // ---- Choosing the plane (Wald and Havran, section 4.2; kd_event_sweep.cpp) -------------------

    Split find_split(const NodeWork& node) const;
    /// The cheapest plane on one axis (sah_sweep.h).
    Split sweep(const NodeWork& node, int axis) const;

    /// What the SAH of one axis needs of a node's cell, and the cell's half surface area (not
    /// positive for a cell reduced to a segment or a point, which no plane can split).
    struct AxisSetup {
        SweepSetup sweep;
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

    // ---- Small nodes (kd_small_node.cpp) ---------------------------------------------------------

    /// The boxes a node's events describe: a start is a box's lower end, an end its upper end, a
    /// planar event both.
    static SmallNode small_node_of(const NodeWork& node);
    void build_small(const SmallNode& node, Subtree& out, std::size_t slot, int depth, int bad_refines) const;
    /// find_split's plane for the node's events, from its boxes.
    Split find_small_split(const SmallNode& node) const;
    /// split_node's children, from the boxes: a box ending on or before the plane goes below, one
    /// starting on or after it above, a flat one in it to the side the split names, and a box
    /// across it (a straddler) to both, clamped to each child's cell (clipped, with perfect splits).
    void split_small(const SmallNode& node, const Split& split, SmallNode& below, SmallNode& above) const;

    // ---- Splitting the node's lists (Wald and Havran, sections 4.3 and 4.4; kd_classify.cpp) -----

    /// Splits the node's triangles and, for a child that may split again (children_may_split and
    /// more than leaf_triangles triangles), its event lists; a child that is a leaf at once gets
    /// its triangles only.
    std::array<NodeWork, 2> split_node(const NodeWork& node, const Split& split, bool children_may_split,
                                       ThreadScratch& scratch) const;

    std::span<const Triangle> file_triangles_;
    std::vector<Triangle> triangles_;  // those with finite corners, in Morton order
    const KdTreeOptions& options_;
    // The plane searches' AVX-512 forms of the portable build's 16-lane file (sah_sweep.h): asked
    // once here, where the build starts, and not in the searches, which run per node and axis.
    const bool avx512_file_searches_ = avx512_file_searches_runnable();
    std::vector<Aabb> bounds_;  // per triangle of triangles_
    int max_depth_ = 0;
    tbb::enumerable_thread_specific<ThreadScratch> scratch_;
};

}  // namespace trident::kd
