#include "accel/bvh/spatial_split_builder.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "accel/bvh/binned_sah_splitter.h"
#include "accel/bvh/build_primitives.h"
#include "accel/bvh/tree_builder.h"

namespace trident::bvh {

namespace {

/// Bins per axis of the object split search (fewer for small nodes, as the binned builder and
/// Embree do) and of the spatial split search (16 built Sponza 1.5x faster but left Room's SAH
/// 8% higher: bench/experiments/bvh-traversal.md).
constexpr int kObjectBins = 32, kSpatialBins = 32, kMaxBins = std::max(kObjectBins, kSpatialBins);
/// Spatial splits are looked for where the object split's children overlap by more than this
/// share of the root's surface area (Stich et al.'s alpha). Their 1e-5 searched far more nodes for
/// the same trees: 1e-2 kept the wide tree's SAH within 0.8% of it on Sponza, Room and Dragon,
/// and built them 2.7-3.7x faster (bench/experiments/bvh-traversal.md).
constexpr double kOverlapShare = 1e-2;
/// Nodes with fewer references are split by objects alone: near the leaves a triangle spans many
/// of a node's spatial bins, so chopping costs most there, while a split saves least.
/// 64 built Sponza 1.3x faster than 16 for 0.3% more SAH (bench/experiments/bvh-traversal.md).
constexpr std::size_t kSpatialMin = 64;
/// Nodes with at least this many references build their children as parallel tasks.
constexpr std::size_t kParallelMin = 4096;

/// A triangle's id and the box of its piece: the whole triangle's box until a spatial split cuts it.
struct Reference {
    Aabb box;
    TriangleId id;

    float centroid(int axis) const { return (box.lo[axis] + box.hi[axis]) * 0.5f; }
};

Aabb bounds_of(std::span<const Reference> refs) {
    Aabb box;
    for (const Reference& r : refs) box.extend(r.box);
    return box;
}

/// The box of the references' centroids (the centres of their boxes), what object splits bin.
Aabb centroid_bounds_of(std::span<const Reference> refs) {
    Aabb box;
    for (const Reference& r : refs) box.extend(r.box.center());
    return box;
}

/// A point computed in double as a box rounded outward to floats, at least one float step beyond
/// the nearest float each way (a step is at most 2^-23 of the value, or the smallest normal
/// float's step near zero), except on `axis`, where it lies exactly on `plane`.
Aabb rounded_outward(const Vec3d& point, int axis, float plane) {
    Aabb box;
    for (int k = 0; k < 3; ++k) {
        const auto nearest = float(point[k]);
        const float slack = std::abs(nearest) * 0x1p-22f + 0x1p-126f;
        box.lo[k] = k == axis ? plane : nearest - slack;
        box.hi[k] = k == axis ? plane : nearest + slack;
    }
    return box;
}

/// The boxes of the triangle's parts below and above `plane` on `axis`, within `box` (the piece
/// being cut): the corners on each side and the edges' crossings of the plane (Stich et al.'s
/// reference split), the crossings computed in double and rounded outward, so that the two boxes
/// together cover the piece. Either may be empty.
std::pair<Aabb, Aabb> cut(const Triangle& tri, const Aabb& box, int axis, float plane) {
    const Vec3f corners[3] = {tri.a, tri.b, tri.c};
    Aabb below, above;
    for (int i = 0; i < 3; ++i) {
        const Vec3f& p = corners[i];
        const Vec3f& q = corners[(i + 1) % 3];
        if (p[axis] <= plane) below.extend(p);
        if (p[axis] >= plane) above.extend(p);
        if ((p[axis] < plane && q[axis] > plane) || (p[axis] > plane && q[axis] < plane)) {
            const double t = (double(plane) - p[axis]) / (double(q[axis]) - p[axis]);
            const Aabb crossing = rounded_outward(Vec3d(p) + (Vec3d(q) - Vec3d(p)) * t, axis, plane);
            below.extend(crossing);
            above.extend(crossing);
        }
    }
    Aabb below_in_box{max(below.lo, box.lo), min(below.hi, box.hi)};
    Aabb above_in_box{max(above.lo, box.lo), min(above.hi, box.hi)};
    below_in_box.hi[axis] = std::min(below_in_box.hi[axis], plane);
    above_in_box.lo[axis] = std::max(above_in_box.lo[axis], plane);
    return {below_in_box, above_in_box};
}

/// A node's children, with their boxes.
struct Children {
    std::vector<Reference> left, right;
    Aabb left_bounds, right_bounds;
    int axis;
};

struct Split {
    double cost = std::numeric_limits<double>::infinity();
    int axis = -1;
    int boundary = 0;  // object: bins [0, boundary) go left; spatial: the plane between bins boundary - 1 and boundary
    Aabb left_bounds, right_bounds;  // object splits only
};

/// A subtree built on its own: nodes indexed from its first, leaves indexing its own ids.
struct Subtree {
    std::vector<BvhNode> nodes;
    std::vector<TriangleId> ids;

    /// Appends a subtree's nodes (indexed from its first) and leaf ids, their indices moved past
    /// what this subtree holds.
    void splice(std::span<const BvhNode> other_nodes, std::span<const TriangleId> other_ids) {
        const auto node_base = std::uint32_t(nodes.size()), id_base = std::uint32_t(ids.size());
        for (BvhNode node : other_nodes) {
            node.index += node.is_leaf() ? id_base : node_base;
            nodes.push_back(node);
        }
        ids.insert(ids.end(), other_ids.begin(), other_ids.end());
    }
};

class Builder {
public:
    Builder(std::span<const Triangle> triangles, const BvhOptions& options, double root_area)
        : triangles_(triangles), options_(options), overlap_limit_(kOverlapShare * root_area) {}

    /// `refs` is consumed. `budget`: the references this subtree may add by cutting triangles.
    Subtree build(std::vector<Reference> refs, const Aabb& bounds, std::uint32_t depth, double budget) const {
        Subtree out;
        append(refs, bounds, depth, budget, out);
        return out;
    }

private:
    void append(std::vector<Reference>& refs, const Aabb& bounds, std::uint32_t depth, double budget,
                Subtree& out) const {
        const std::size_t count = refs.size();
        if (!may_split_spatially(count, bounds, budget)) {
            append_binned(refs, depth, out);
            return;
        }
        Children children;
        if (!split(refs, bounds, depth, budget, children)) {
            const std::size_t first = out.ids.size();
            for (const Reference& r : refs)  // pieces of one triangle may meet again in a leaf: test it once
                if (std::find(out.ids.begin() + std::ptrdiff_t(first), out.ids.end(), r.id) == out.ids.end())
                    out.ids.push_back(r.id);
            out.nodes.push_back(BvhNode::leaf(bounds, std::uint32_t(first), std::uint32_t(out.ids.size() - first)));
            return;
        }
        std::vector<Reference>().swap(refs);  // free the parent's references before the children's
        const std::size_t left_count = children.left.size(), right_count = children.right.size();
        const double remaining = std::max(0.0, budget - double(left_count + right_count - count));
        const double left_budget = remaining * double(left_count) / double(left_count + right_count);
        const std::size_t index = out.nodes.size();
        out.nodes.push_back(BvhNode::interior(bounds, children.axis, 0));
        if (count >= kParallelMin) {
            Subtree left, right;
            tbb::parallel_invoke(
                [&] { left = build(std::move(children.left), children.left_bounds, depth + 1, left_budget); },
                [&] {
                    right = build(std::move(children.right), children.right_bounds, depth + 1, remaining - left_budget);
                });
            Subtree parent_and_left{std::move(out.nodes), std::move(out.ids)};
            parent_and_left.splice(left.nodes, left.ids);
            parent_and_left.nodes[index].index = std::uint32_t(parent_and_left.nodes.size());
            parent_and_left.splice(right.nodes, right.ids);
            out = std::move(parent_and_left);
            return;
        }
        append(children.left, children.left_bounds, depth + 1, left_budget, out);
        out.nodes[index].index = std::uint32_t(out.nodes.size());
        append(children.right, children.right_bounds, depth + 1, remaining - left_budget, out);
    }

    /// Whether this node or one below it may take a spatial split (split() looks for one only
    /// where this holds). A child's box lies in its node's and holds no more references, and two
    /// children overlap within their node's box, so where this is false it stays false below.
    bool may_split_spatially(std::size_t count, const Aabb& bounds, double budget) const {
        return budget >= 1.0 && count >= kSpatialMin && surface_area_in_double(bounds) > overlap_limit_;
    }

    /// The subtree of a node that can take no spatial split, built by the binned builder
    /// (TreeBuilder over BinnedSahSplitter), as the binned build would build it from these boxes.
    /// Below the large nodes where spatial splits may pay, that is most of the nodes: the binned
    /// builder bins 8 lanes at a time and refines its splits, where this builder's own object
    /// search bins one reference at a time in fixed bins. Handing the subtrees over built the study
    /// scenes in 0.78-0.96 of the time, for the same or a lower SAH; the top levels' spatial search
    /// is what remains of the cost (bench/experiments/bvh-build.md).
    void append_binned(const std::vector<Reference>& refs, std::uint32_t depth, Subtree& out) const {
        std::vector<PrimitiveRef> prims;
        prims.reserve(refs.size());
        for (const Reference& r : refs) prims.emplace_back(r.box, r.id);
        BinnedSahSplitter splitter(prims, options_);
        const HugePageArray<BvhNode> nodes = TreeBuilder(splitter, options_).build(whole_range(prims), depth);
        std::vector<TriangleId> ids;
        ids.reserve(prims.size());
        for (const PrimitiveRef& prim : prims) ids.push_back(prim.id);  // in leaf order after the build
        out.splice(nodes, ids);
    }

    /// The node's children, or false for a leaf. A node that fits one block of the wide BVH gets
    /// an object split only where the collapse's cost says so (BvhOptions::split_beats_block);
    /// otherwise SAH decides between a leaf, the best object split
    /// and the best spatial split; a node SAH would leave too large gets a median split. The
    /// depth bound is TreeBuilder::split_node's: SAH splits only while median splits could still
    /// finish the subtree within kBvhMaxDepth (a child holds at most as many references as its
    /// node, so the bound holds for it when it falls back to median splits).
    bool split(const std::vector<Reference>& refs, const Aabb& bounds, std::uint32_t depth, double budget,
               Children& children) const {
        const std::size_t count = refs.size();
        if (count <= 1) return false;
        const double area = surface_area_in_double(bounds);
        if (depth + 1 + std::uint32_t(std::bit_width(count - 1)) <= kBvhMaxDepth) {
            const double leaf_cost = double(options_.intersection_cost) * double(count) * area;
            const Aabb centroids = centroid_bounds_of(refs);
            const Split object = best_object_split(refs, centroids, area);
            if (options_.fits_one_block(std::uint32_t(count))) {
                if (object.axis < 0) return false;
                partition_object(refs, centroids, object, children);
                return BvhOptions::split_beats_block(children.left_bounds.surface_area(),
                                                     children.right_bounds.surface_area(), bounds.surface_area());
            }
            Split spatial;
            const Aabb overlap{max(object.left_bounds.lo, object.right_bounds.lo),
                               min(object.left_bounds.hi, object.right_bounds.hi)};
            if (object.axis < 0 || surface_area_in_double(overlap) > overlap_limit_)  // may_split_spatially() holds
                spatial = best_spatial_split(refs, bounds, area, budget);
            if (spatial.cost < object.cost && spatial.cost < leaf_cost &&
                partition_spatial(refs, bounds, spatial, children))
                return true;
            if (object.cost < leaf_cost) {
                partition_object(refs, centroids, object, children);
                return true;
            }
        }
        if (count <= std::size_t(options_.max_leaf_size)) return false;
        partition_median(refs, children);
        return true;
    }

    static int object_bins(std::size_t count) { return int(std::min<std::size_t>(kObjectBins, 4 + count / 4)); }

    /// Centroids in object_bins() bins per axis of their box; the SAH at every bin boundary.
    Split best_object_split(const std::vector<Reference>& refs, const Aabb& centroids, double area) const {
        const int bins = object_bins(refs.size());
        const Vec3f extent = centroids.extent();
        std::array<std::array<Aabb, kObjectBins>, 3> boxes;  // one pass over the references for all three axes
        std::array<std::array<std::uint32_t, kObjectBins>, 3> counts{};
        for (const Reference& r : refs)
            for (int axis = 0; axis < 3; ++axis) {
                if (!(extent[axis] > 0.0f)) continue;
                const int b = object_bin(r.centroid(axis), centroids.lo[axis], extent[axis], bins);
                boxes[axis][b].extend(r.box);
                ++counts[axis][b];
            }
        Split best;
        for (int axis = 0; axis < 3; ++axis) {
            if (!(extent[axis] > 0.0f)) continue;
            const auto axis_counts = std::span<const std::uint32_t>(counts[axis]).first(std::size_t(bins));
            sweep(std::span<const Aabb>(boxes[axis]).first(std::size_t(bins)), axis_counts, axis_counts, refs.size(),
                  area, axis, best);
        }
        return best;
    }

    static int object_bin(float centroid, float lo, float extent, int bins) {
        return std::clamp(int((centroid - lo) * (float(bins) / extent)), 0, bins - 1);
    }

    /// The plane between spatial bins k - 1 and k (1 <= k < kSpatialBins) of `bounds` on `axis`.
    static float plane(const Aabb& bounds, int axis, int k) {
        return float(double(bounds.lo[axis]) + (double(bounds.hi[axis]) - bounds.lo[axis]) * k / kSpatialBins);
    }

    /// Each reference chopped at the planes of kSpatialBins equal bins of the node's box, its pieces'
    /// boxes grown into the bins they fall in, counted where it enters and where it leaves (Stich et
    /// al.'s chopped binning); the SAH at every plane, within the budget of references.
    Split best_spatial_split(const std::vector<Reference>& refs, const Aabb& bounds, double area, double budget) const {
        Split best;
        for (int axis = 0; axis < 3; ++axis) {
            if (!(bounds.hi[axis] > bounds.lo[axis])) continue;
            std::array<float, kSpatialBins + 1> planes;
            for (int k = 1; k < kSpatialBins; ++k) planes[k] = plane(bounds, axis, k);
            const auto first = planes.begin() + 1, last = planes.begin() + kSpatialBins;
            std::array<Aabb, kSpatialBins> boxes;
            std::array<std::uint32_t, kSpatialBins> entries{}, exits{};
            for (const Reference& r : refs) {
                // Bin b spans [planes[b], planes[b + 1]): a piece lying on a plane goes below it, as
                // partition_spatial sends it.
                const int exit = int(std::lower_bound(first, last, r.box.hi[axis]) - first);
                const int entry = std::min(exit, int(std::upper_bound(first, last, r.box.lo[axis]) - first));
                Aabb rest = r.box;
                for (int b = entry; b < exit; ++b) {
                    const auto [below, above] = cut(triangles_[r.id], rest, axis, planes[b + 1]);
                    boxes[b].extend(below);
                    rest = above;
                }
                boxes[exit].extend(rest);
                ++entries[entry];
                ++exits[exit];
            }
            Split candidate;
            sweep(boxes, entries, exits, refs.size(), area, axis, candidate, budget);
            if (candidate.cost < best.cost) best = candidate;
        }
        return best;
    }

    /// The SAH at each boundary of `boxes`: left of it the references counted in `left_counts`,
    /// right of it those in `right_counts` (the same for object bins; entries and exits for
    /// spatial ones). Boundaries that leave a child empty, or whose children would add more than
    /// `budget` references, are passed over.
    void sweep(std::span<const Aabb> boxes, std::span<const std::uint32_t> left_counts,
               std::span<const std::uint32_t> right_counts, std::size_t count, double area, int axis, Split& best,
               double budget = 0.0) const {
        const int bins = int(boxes.size());
        std::array<double, kMaxBins> right_area;
        std::array<std::size_t, kMaxBins> right_count;
        std::array<Aabb, kMaxBins> right_box;
        Aabb box;
        std::size_t n = 0;
        for (int b = bins - 1; b > 0; --b) {
            box.extend(boxes[b]);
            n += right_counts[b];
            right_area[b] = surface_area_in_double(box);
            right_count[b] = n;
            right_box[b] = box;
        }
        box = Aabb{};
        n = 0;
        for (int b = 1; b < bins; ++b) {
            box.extend(boxes[b - 1]);
            n += left_counts[b - 1];
            const std::size_t nl = n, nr = right_count[b];
            if (nl == 0 || nr == 0 || double(nl + nr) - double(count) > budget) continue;
            const double cost = double(options_.traversal_cost) * area +
                                double(options_.intersection_cost) *
                                    (surface_area_in_double(box) * double(nl) + right_area[b] * double(nr));
            if (cost < best.cost) best = {cost, axis, b, box, right_box[b]};
        }
    }

    void partition_object(const std::vector<Reference>& refs, const Aabb& centroids, const Split& split,
                          Children& children) const {
        const float lo = centroids.lo[split.axis], extent = centroids.hi[split.axis] - lo;
        const int bins = object_bins(refs.size());
        children.left.reserve(refs.size());
        children.right.reserve(refs.size());
        for (const Reference& r : refs)
            (object_bin(r.centroid(split.axis), lo, extent, bins) < split.boundary ? children.left : children.right)
                .push_back(r);
        children.left_bounds = split.left_bounds;
        children.right_bounds = split.right_bounds;
        children.axis = split.axis;
    }

    /// False when the cut leaves a child empty (the bins' counts are of the pieces' boxes, which
    /// the cut may find empty). A child may keep all of the node's references, in smaller boxes:
    /// each such split spends budget, and the depth bound is checked again at the child.
    bool partition_spatial(const std::vector<Reference>& refs, const Aabb& bounds, const Split& split,
                           Children& children) const {
        const int axis = split.axis;
        const float at = plane(bounds, axis, split.boundary);
        children.left.reserve(refs.size());
        children.right.reserve(refs.size());
        for (const Reference& r : refs) {
            if (r.box.hi[axis] <= at) {
                children.left.push_back(r);
            } else if (r.box.lo[axis] >= at) {
                children.right.push_back(r);
            } else {
                const auto [below, above] = cut(triangles_[r.id], r.box, axis, at);
                if (!below.is_empty()) children.left.push_back({below, r.id});
                if (!above.is_empty()) children.right.push_back({above, r.id});
            }
        }
        if (children.left.empty() || children.right.empty()) {
            children = Children{};
            return false;
        }
        children.left_bounds = bounds_of(children.left);
        children.right_bounds = bounds_of(children.right);
        children.axis = axis;
        return true;
    }

    /// The object median along the axis of largest centroid extent (any halves when all coincide).
    static void partition_median(const std::vector<Reference>& refs, Children& children) {
        const int axis = centroid_bounds_of(refs).largest_axis();
        std::vector<Reference> sorted = refs;
        const auto middle = sorted.begin() + std::ptrdiff_t(sorted.size() / 2);
        std::nth_element(sorted.begin(), middle, sorted.end(), [axis](const Reference& a, const Reference& b) {
            return a.centroid(axis) < b.centroid(axis) || (a.centroid(axis) == b.centroid(axis) && a.id < b.id);
        });
        children.left.assign(sorted.begin(), middle);
        children.right.assign(middle, sorted.end());
        children.left_bounds = bounds_of(children.left);
        children.right_bounds = bounds_of(children.right);
        children.axis = axis;
    }

    std::span<const Triangle> triangles_;
    const BvhOptions& options_;
    double overlap_limit_;
};

}  // namespace

SpatialSplitTree build_with_spatial_splits(const Mesh& mesh, const BvhOptions& options) {
    SpatialSplitTree tree;
    if (mesh.triangle_count() == 0) return tree;
    const std::vector<Triangle> triangles = gather_triangles(mesh);
    std::vector<Reference> refs(triangles.size());
    Aabb bounds;
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        const Aabb box = triangles[i].bounds();
        refs[i] = {{box.lo + Vec3f{0.0f}, box.hi + Vec3f{0.0f}}, TriangleId(i)};  // -0 + +0 = +0
        bounds.extend(refs[i].box);
    }
    const Builder builder(triangles, options, surface_area_in_double(bounds));
    const Subtree built =
        builder.build(std::move(refs), bounds, 0, double(options.spatial_split_budget) * double(triangles.size()));
    tree.nodes.assign(built.nodes.begin(), built.nodes.end());
    tree.leaf_ids.assign(built.ids.begin(), built.ids.end());
    return tree;
}

}  // namespace trident::bvh
