#pragma once
// Scalar single-ray traversal of the flattened octree: the parametric walk of Revelles et al.
// (octree_walk.h), made iterative with a fixed stack of one frame per level, front to back.
// Closest hit and any hit are one function with a compile-time query.
#include <array>
#include <cmath>
#include <cstdint>
#include <span>

#include "accel/octree/octree_build.h"
#include "accel/octree/octree_node.h"
#include "accel/octree/octree_walk.h"
#include "core/flatten.h"
#include "core/intersect_triangle.h"

namespace trident {

/// The arrays a traversal reads (see OctreeLayout): nodes (root first), the leaves' triangle
/// positions, the triangles in Morton order with their file-order ids, and the root cube.
struct OctreeView {
    std::span<const OctreeNode> nodes;
    std::span<const std::uint32_t> triangle_indices;
    std::span<const Triangle> triangles;
    std::span<const TriangleId> triangle_ids;
    OctreeCube cube;
};

enum class OctreeQuery { closest_hit, any_hit };

/// One ray's walk through the subtree of `root` (with cell `root_cell` and slabs `root_slabs` along
/// the ray), front to back, lowering `best` (its t is the triangle tests' limit). Returns true when
/// the ray is finished: its query is answered, or a cell it would enter lies beyond its closest
/// hit, and so does every cell after it. Packets walk subtrees of few lanes with it.
///
/// Flattened (every call in it inlined): gcc otherwise calls the triangle test out of line, once
/// per triangle, and the walk took up to 1.56 times as long (bench/experiments/packets.md).
template <OctreeQuery Query, TriangleTest Test, SlabTest Slabs, class Counters>
TRIDENT_FLATTEN bool walk_octree_subtree(const OctreeView& tree, const OctreeWalkRay& walk,
                                         const TriangleIntersector<Test>& intersector, float tmin,
                                         const OctreeNode& root, const NodeSlabs& root_slabs,
                                         const OctreeCube& root_cell, Hit& best, Counters& counters) {
    struct Frame {
        NodeSlabs slabs;
        Vec3f tm;
        OctreeCube cell;  // real (unmirrored) cell: the walk reads it on axes the ray runs parallel to
        OctreeNode node;
        unsigned next;  // the next child to visit, mirrored numbering; 8 when done
    };
    std::array<Frame, kOctreeMaxDepth> stack;  // interior nodes sit at levels 0 .. max depth - 1
    std::size_t top = 0;

    // Visits a node: an interior node is pushed, a leaf's triangles are tested. True when the
    // query is answered.
    auto visit = [&](const OctreeNode& node, const NodeSlabs& slabs, const OctreeCube& cell) {
        counters.visit_node();
        if (!node.is_leaf()) {
            const Vec3f tm = slab_midpoints(walk, slabs, cell);
            stack[top++] = {slabs, tm, cell, node, first_child(slabs, tm)};
            return false;
        }
        const std::uint32_t end = node.triangle_offset() + node.triangle_count();
        for (std::uint32_t i = node.triangle_offset(); i < end; ++i) {
            const std::uint32_t position = tree.triangle_indices[i];
            counters.test_triangle();
            TriangleHit h;
            if (!intersector.intersect(tree.triangles[position], best.t, h)) continue;
            best = {tree.triangle_ids[position], h.t, h.u, h.v};
            if constexpr (Query == OctreeQuery::any_hit) return true;
        }
        // A triangle reaches into several cells, so a hit may lie beyond this cell where a later
        // cell could hold a nearer one: the hit ends the ray only if it lies before this cell's
        // exit (every cell left starts there). The exit is widened by a few ulps so that hits on
        // a cell's face (axis-aligned walls on a centre plane) do not push the ray through the
        // next cells for nothing; that is safe because a nearer hit within those ulps of the face
        // is on a triangle the builder, whose cells are widened by far more, put in this cell too.
        return best.is_hit() && best.t <= widened_cell_exit<Slabs>(slabs.t_exit());
    };

    if (visit(root, root_slabs, root_cell)) return true;
    while (top > 0) {
        Frame& frame = stack[top - 1];
        if (frame.next == 8u) {
            --top;
            continue;
        }
        const unsigned child = frame.next;
        const NodeSlabs slabs = child_slabs(child, frame.slabs, frame.tm);
        frame.next = next_child(child, slabs);
        const unsigned real_child = child ^ walk.mirror;
        if (!frame.node.has_child(real_child) || slabs.t_exit() < tmin) continue;
        if (slabs.t_enter() > best.t) return true;  // front to back: every cell left lies beyond it
        if (visit(tree.nodes[frame.node.child_slot(real_child)], slabs, child_cube(frame.cell, real_child)))
            return true;
    }
    return false;
}

/// Traces `ray` through `tree`. Closest hit: the nearest hit with tmin <= t < tmax, or a miss
/// (triangle kNoTriangle, t = +inf). Any hit: the first hit found, or a miss.
template <OctreeQuery Query, TriangleTest Test, SlabTest Slabs = SlabTest::robust, class Counters>
Hit traverse_octree(const OctreeView& tree, const Ray& ray, Counters& counters) {
    OctreeWalkRay walk;
    NodeSlabs root;
    if (!enter_root(ray, tree.cube, walk, root)) return Hit{};
    if (root.t_enter() > root.t_exit() || root.t_exit() < ray.tmin || root.t_enter() > ray.tmax) return Hit{};

    const TriangleIntersector<Test> intersector(ray);
    Hit best;
    best.t = ray.tmax;  // the triangle tests' limit, lowered by every hit
    walk_octree_subtree<Query, Test, Slabs>(tree, walk, intersector, ray.tmin, tree.nodes[0], root, tree.cube, best,
                                            counters);
    if (!best.is_hit()) best.t = kInfinity;
    return best;
}

}  // namespace trident
