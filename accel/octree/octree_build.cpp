#include "accel/octree/octree_build.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "accel/octree/morton_order.h"
#include "core/triangle_box_overlap.h"

namespace trident {

void validate(const OctreeOptions& options) {
    if (options.max_depth < 0 || options.max_depth > kOctreeMaxDepth)
        throw std::invalid_argument(
            fmt::format("octree: the maximum depth must be between 1 and {} (0 for the default), not {}",
                        kOctreeMaxDepth, options.max_depth));
}

namespace {

bool is_finite(const Triangle& tri) { return is_finite(tri.a) && is_finite(tri.b) && is_finite(tri.c); }

float max_abs_coordinate(const Vec3f& lo, const Vec3f& hi) {
    return std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y), std::abs(hi.z)});
}

/// How far every cell is widened before overlap tests, so that rounding in the builder and in the
/// traversal's parametric planes never separates a triangle from a cell it touches. The traversal
/// walks planes that are off by a few ulps of the ray parameter, which is far below 2^-16 of the
/// root for any camera within ~30 scene sizes; the second term covers scenes far from the origin.
float cell_widening(const OctreeCube& cube) {
    return cube.size * 0x1p-16f + max_abs_coordinate(cube.lo, cube.lo + Vec3f(cube.size)) * 0x1p-20f;
}

/// The deepest level whose cells stay at least 16 times the widening above. Far from the origin
/// the widening's second term (a few ulps of the coordinates) can exceed a deep cell's size; every
/// triangle would then be referenced by every nearby cell and the traversal would step through
/// cells smaller than the ray's rounding, so the default depth stops there instead.
int precision_depth_limit(const OctreeCube& cube) {
    const double cells_across = double(cube.size) / (16.0 * double(cell_widening(cube)));
    return cells_across < 2.0 ? 1 : std::max(1, int(std::floor(std::log2(cells_across))));
}

struct BuildContext {
    std::span<const Triangle> triangles;
    std::size_t min_primitives;
    int max_depth;
    OctreeOverlap overlap;
    float widening;
    std::uint64_t budget;  // the reference guard
};

// The children in the lower and in the upper half of each axis.
constexpr std::array<unsigned, 3> kLowerChildren = {0x55u, 0x33u, 0x0Fu};
constexpr std::array<unsigned, 3> kUpperChildren = {0xAAu, 0xCCu, 0xF0u};

/// The mask of the (widened) children of `cell` the triangle overlaps. The bounding box against the
/// centre planes narrows the candidates; a triangle with a single candidate overlaps it (it
/// overlaps the parent and lies on that side of every plane), so only triangles that straddle a
/// plane pay for separating-axis tests.
unsigned overlapped_children(const Triangle& tri, const OctreeCube& cell, const BuildContext& ctx) {
    const Aabb box = tri.bounds();
    const Vec3f mid = cell.mid();
    unsigned candidates = 0xFFu;
    for (int axis = 0; axis < 3; ++axis) {
        unsigned sides = 0;
        if (box.lo[axis] <= mid[axis] + ctx.widening) sides |= kLowerChildren[axis];
        if (box.hi[axis] >= mid[axis] - ctx.widening) sides |= kUpperChildren[axis];
        candidates &= sides;
    }
    if (ctx.overlap == OctreeOverlap::bounding_box || std::has_single_bit(candidates)) return candidates;
    const float quarter = cell.size * 0.25f;
    const Vec3f half_extent(quarter + ctx.widening);
    unsigned overlapped = 0;
    for (unsigned rest = candidates; rest != 0; rest &= rest - 1) {
        const unsigned child = unsigned(std::countr_zero(rest));
        const Vec3f centre = child_cube(cell, child).lo + Vec3f(quarter);
        if (triangle_overlaps_box(tri.a, tri.b, tri.c, centre, half_extent)) overlapped |= 1u << child;
    }
    // The union of the widened children is the widened parent, which the triangle overlaps; if
    // rounding ever rejected every child, keep the triangle in all candidates rather than drop it.
    return overlapped != 0 ? overlapped : candidates;
}

/// A node of the level being split: its slot in the node array, its cell, and its references
/// (a range of the level's reference array).
struct LevelNode {
    std::uint32_t slot;
    OctreeCube cell;
    std::size_t first_ref;
    std::size_t ref_count;
};

using ChildCounts = std::array<std::size_t, 8>;

// Grain sizes of the parallel loops: references are classified in chunks of this many, nodes
// are counted and copied in groups of this many (a task per node would cost more than the node).
constexpr std::size_t kReferencesPerTask = 4096;
constexpr std::size_t kNodesPerTask = 64;

/// Whether a node of `count` references at `depth` is split at all, before its children are known.
bool may_split(std::size_t count, int depth, const BuildContext& ctx) {
    return depth < ctx.max_depth && count > ctx.min_primitives;
}

/// Per reference of the level, the children it goes to (0 for nodes that will not be split). In
/// parallel over ranges of references, so one huge node (the root) is spread over all threads.
void classify_level(std::span<const LevelNode> level, std::span<const std::uint32_t> refs, int depth,
                    const BuildContext& ctx, std::vector<std::uint8_t>& child_masks) {
    child_masks.assign(refs.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, refs.size(), kReferencesPerTask), [&](const auto& range) {
        auto node = std::upper_bound(level.begin(), level.end(), range.begin(),
                                     [](std::size_t i, const LevelNode& n) { return i < n.first_ref; }) -
                    1;
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
            while (i >= node->first_ref + node->ref_count) ++node;
            if (may_split(node->ref_count, depth, ctx))
                child_masks[i] = std::uint8_t(overlapped_children(ctx.triangles[refs[i]], node->cell, ctx));
        }
    });
}

std::vector<ChildCounts> count_children(std::span<const LevelNode> level, std::span<const std::uint8_t> child_masks) {
    std::vector<ChildCounts> counts(level.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, level.size(), kNodesPerTask), [&](const auto& nodes) {
        for (std::size_t n = nodes.begin(); n < nodes.end(); ++n) {
            ChildCounts& c = counts[n];
            c.fill(0);
            for (std::uint8_t mask : child_masks.subspan(level[n].first_ref, level[n].ref_count))
                for (unsigned rest = mask; rest != 0; rest &= rest - 1) ++c[std::size_t(std::countr_zero(rest))];
        }
    });
    return counts;
}

double area_weight(int depth) { return std::ldexp(1.0, -2 * depth); }

/// Where a node's references go: a leaf's into the triangle-index list, a split node's into its
/// children's ranges of the next level.
struct CopyJob {
    std::size_t node;  // in the level
    bool leaf;
    std::array<std::size_t, 8> dest;  // leaf: dest[0], its offset; split: each child's first reference
};

/// The state between levels.
struct LevelState {
    std::vector<LevelNode> nodes;
    std::vector<std::uint32_t> refs;
    /// The references the tree would hold if no node split further; kept within the budget.
    std::uint64_t committed = 0;
};

/// Decides, in level order, which nodes split, and writes their nodes; this sequential pass is
/// what keeps the reference guard (and so the tree) independent of the thread count. A node
/// splits while the references its children add fit in what is left of the budget.
std::vector<CopyJob> decide_splits(const LevelState& level, std::span<const ChildCounts> counts, int depth,
                                   const BuildContext& ctx, LevelState& next, OctreeLayout& layout) {
    OctreeBuildTotals& totals = layout.totals;
    std::vector<CopyJob> jobs;
    jobs.reserve(level.nodes.size());
    next.nodes.clear();
    next.committed = level.committed;
    std::size_t next_refs = 0;
    for (std::size_t n = 0; n < level.nodes.size(); ++n) {
        const LevelNode& node = level.nodes[n];
        const ChildCounts& c = counts[n];
        std::size_t children_refs = 0;
        for (std::size_t k : c) children_refs += k;
        // Splitting cannot separate anything when every child gets every triangle (e.g. all of
        // them through one point): a leaf is as good and keeps the tree small.
        bool split = may_split(node.ref_count, depth, ctx) &&
                     !std::all_of(c.begin(), c.end(), [&](std::size_t k) { return k == node.ref_count; });
        if (split && next.committed - node.ref_count + children_refs > ctx.budget) {
            split = false;
            ++totals.budget_stops;
        }
        CopyJob& job = jobs.emplace_back(CopyJob{n, !split, {}});
        if (!split) {
            job.dest[0] = totals.references;
            layout.nodes[node.slot] = OctreeNode::leaf(std::uint32_t(totals.references), std::uint32_t(node.ref_count));
            ++totals.leaves;
            totals.references += node.ref_count;
            totals.max_leaf_size = std::max(totals.max_leaf_size, node.ref_count);
            totals.depth = std::max(totals.depth, std::size_t(depth));
            totals.sah_cost += area_weight(depth) * double(node.ref_count);
            continue;
        }
        next.committed = next.committed - node.ref_count + children_refs;
        unsigned child_mask = 0;
        for (unsigned k = 0; k < 8; ++k)
            if (c[k] != 0) child_mask |= 1u << k;
        const auto first = std::uint32_t(layout.nodes.size());
        const int stored = std::popcount(child_mask);
        layout.nodes.resize(layout.nodes.size() + std::size_t(stored));
        layout.nodes[node.slot] = OctreeNode::interior(first, child_mask);
        for (unsigned k = 0, rank = 0; k < 8; ++k) {
            if (c[k] == 0) continue;
            job.dest[k] = next_refs;
            next.nodes.push_back({first + rank++, child_cube(node.cell, k), next_refs, c[k]});
            next_refs += c[k];
        }
        totals.empty_children += std::size_t(8 - stored);
        totals.sah_cost += area_weight(depth);
    }
    next.refs.resize(next_refs);
    layout.triangle_indices.resize(totals.references);
    return jobs;
}

/// Carries out the jobs, in parallel over nodes (they write disjoint ranges).
void copy_references(std::span<const CopyJob> jobs, const LevelState& level, std::span<const std::uint8_t> child_masks,
                     LevelState& next, std::vector<std::uint32_t>& triangle_indices) {
    auto copy = [&](const CopyJob& job) {
        const LevelNode& node = level.nodes[job.node];
        const auto refs = std::span(level.refs).subspan(node.first_ref, node.ref_count);
        if (job.leaf) {
            std::copy(refs.begin(), refs.end(), triangle_indices.begin() + std::ptrdiff_t(job.dest[0]));
            return;
        }
        std::array<std::size_t, 8> cursor = job.dest;
        for (std::size_t i = 0; i < refs.size(); ++i)
            for (unsigned rest = child_masks[node.first_ref + i]; rest != 0; rest &= rest - 1)
                next.refs[cursor[std::size_t(std::countr_zero(rest))]++] = refs[i];
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, jobs.size(), kNodesPerTask), [&](const auto& range) {
        for (std::size_t j = range.begin(); j < range.end(); ++j) copy(jobs[j]);
    });
}

}  // namespace

OctreeCube octree_root_cube(std::span<const Triangle> triangles) {
    Aabb box;
    for (const Triangle& tri : triangles)
        if (is_finite(tri)) box.extend(tri.bounds());
    if (box.is_empty()) return {Vec3f(0.0f), 0.0f};
    const Vec3f extent = box.extent();
    const float edge = std::max({extent.x, extent.y, extent.z});
    // A pad of 2^-20 of the larger of the edge and the coordinates (many ulps of both) keeps every
    // triangle strictly inside, so rays grazing the cube's faces cannot round past a triangle.
    const float pad = std::max(std::max(edge, max_abs_coordinate(box.lo, box.hi)) * 0x1p-20f, 1e-30f);
    return {box.lo - Vec3f(pad), edge + 2.0f * pad};
}

int default_octree_depth(std::span<const std::uint32_t> sorted_morton_keys) {
    // Tuned on the built-in and the benchmark scenes (480x270 primary rays, depths 5 to 10); see
    // the header for what each gets.
    constexpr std::size_t kTrianglesPerCell = 10;
    constexpr int kDeepestDefault = 9;
    if (sorted_morton_keys.empty()) return 1;
    const std::vector<std::size_t> occupied = occupied_cells_per_depth(sorted_morton_keys);
    for (int depth = 1; depth < kDeepestDefault; ++depth)
        if (sorted_morton_keys.size() <= kTrianglesPerCell * occupied[std::size_t(depth)]) return depth;
    return kDeepestDefault;
}

OctreeLayout build_octree_layout(std::span<const Triangle> triangles, const OctreeOptions& options) {
    validate(options);
    if (triangles.size() > OctreeNode::kMaxLeafCount)
        throw std::length_error(fmt::format("octree: {} triangles is more than the {} a leaf can index",
                                            triangles.size(), OctreeNode::kMaxLeafCount));
    OctreeLayout layout;
    layout.cube = octree_root_cube(triangles);
    std::vector<std::uint32_t> finite;
    finite.reserve(triangles.size());
    for (std::size_t i = 0; i < triangles.size(); ++i)
        if (is_finite(triangles[i])) finite.push_back(std::uint32_t(i));
    MortonSorted sorted = sort_by_morton_key(triangles, std::move(finite), layout.cube);
    layout.max_depth = options.max_depth != 0
                           ? options.max_depth
                           : std::min(default_octree_depth(sorted.keys), precision_depth_limit(layout.cube));
    layout.triangle_ids = std::move(sorted.indices);
    layout.triangles.reserve(layout.triangle_ids.size());
    for (TriangleId id : layout.triangle_ids) layout.triangles.push_back(triangles[id]);
    const std::size_t skipped = triangles.size() - layout.triangles.size();

    LevelState level, next;
    level.refs.resize(layout.triangles.size());
    std::iota(level.refs.begin(), level.refs.end(), 0u);
    level.nodes = {{0, layout.cube, 0, level.refs.size()}};
    level.committed = level.refs.size();
    layout.nodes.resize(1);

    constexpr std::uint64_t kIndexLimit = std::numeric_limits<std::uint32_t>::max();
    const std::uint64_t budget = std::min<std::uint64_t>(
        options.max_references != 0 ? options.max_references : 64 * std::uint64_t(triangles.size()) + (1u << 20),
        kIndexLimit);
    const BuildContext ctx{layout.triangles, options.min_primitives,     layout.max_depth,
                           options.overlap,  cell_widening(layout.cube), budget};

    // Level by level: every step is parallel except the decisions, which are cheap and in order.
    std::vector<std::uint8_t> child_masks;
    for (int depth = 0; !level.nodes.empty(); ++depth) {
        classify_level(level.nodes, level.refs, depth, ctx, child_masks);
        const std::vector<ChildCounts> counts = count_children(level.nodes, child_masks);
        const std::vector<CopyJob> jobs = decide_splits(level, counts, depth, ctx, next, layout);
        copy_references(jobs, level, child_masks, next, layout.triangle_indices);
        std::swap(level, next);
    }
    layout.totals.nodes = layout.nodes.size();

    if (skipped != 0)
        layout.warning = fmt::format("octree: {} triangles with non-finite coordinates were left out", skipped);
    if (layout.totals.budget_stops != 0) {
        if (!layout.warning.empty()) layout.warning += "; ";
        layout.warning += fmt::format(
            "octree: the reference guard of {} stopped {} nodes from splitting (the tree holds {} references "
            "for {} triangles); raise max_references or lower the depth",
            budget, layout.totals.budget_stops, layout.totals.references, triangles.size());
    }
    return layout;
}

}  // namespace trident
