#pragma once
// What the BVH builders work on: one reference per triangle (its box and file-order id) and the
// ranges of references a node covers while the tree is built.
#include <cstdint>
#include <span>
#include <vector>

#include "core/aabb.h"
#include "core/huge_page_array.h"
#include "core/mesh.h"
#include "core/ray.h"

namespace trident::bvh {

/// A triangle's box and id in 32 bytes, aligned so that a reference is one 8-lane load: `lo` and
/// the id load as one 4-lane vector, `hi` and a zero as another, which is how the binning reads
/// them (binned_sah_splitter.cpp).
struct alignas(32) PrimitiveRef {
    float lo[3];
    TriangleId id;
    float hi[3];
    float zero;  // a harmless fourth lane for hi

    PrimitiveRef() = default;  // trivial, so scratch arrays need not be written before use
    PrimitiveRef(const Aabb& box, TriangleId id_)
        : lo{box.lo.x, box.lo.y, box.lo.z}, id(id_), hi{box.hi.x, box.hi.y, box.hi.z}, zero(0.0f) {}

    Aabb bounds() const { return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}; }
    /// The centre of the box: the point the builders bin and sort, as pbrt and Embree do (cheaper
    /// to keep than the corners' mean, and as good a representative for SAH).
    float centroid(int axis) const { return (lo[axis] + hi[axis]) * 0.5f; }
    Vec3f centroid() const { return {centroid(0), centroid(1), centroid(2)}; }
};
static_assert(sizeof(PrimitiveRef) == 32);

/// The references [begin, end) of one node, the union of their boxes and of their centroids.
struct BuildRange {
    std::uint32_t begin = 0, end = 0;
    Aabb bounds;
    Aabb centroid_bounds;

    std::uint32_t count() const { return end - begin; }
};

/// A node's two children and the axis they were split on.
struct ChildRanges {
    BuildRange left, right;
    int axis;
};

/// One reference per triangle in file order, computed in parallel. Box coordinates of -0 become
/// +0, so min/max reductions give the same bits whatever order threads combine them in.
HugePageArray<PrimitiveRef> make_primitive_refs(const Mesh& mesh);

/// The range covering all of `refs`, its unions reduced in parallel.
BuildRange whole_range(std::span<const PrimitiveRef> refs);

}  // namespace trident::bvh
