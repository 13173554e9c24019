#pragma once
// Independent checks for the octree tests: exact cells walked from the root, triangle/box
// overlap by clipping (a different algorithm from the builder's separating axes), slab
// intervals in double; and rays the traversal tests share.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include "accel/octree/octree.h"
#include "core/aabb.h"
#include "support/triangle_box_clipping.h"

namespace trident::testing {

/// Calls visit(node, cell, depth) for every stored node and visit(nullopt, cell, depth) for every
/// empty (unstored) child of an interior node.
inline void for_each_cell(const Octree& tree,
                          const std::function<void(std::optional<OctreeNode>, const OctreeCube&, int)>& visit) {
    struct Item {
        std::uint32_t slot;
        OctreeCube cell;
        int depth;
    };
    std::vector<Item> todo{{0, tree.cube(), 0}};
    while (!todo.empty()) {
        const Item item = todo.back();
        todo.pop_back();
        const OctreeNode node = tree.nodes()[item.slot];
        visit(node, item.cell, item.depth);
        if (node.is_leaf()) continue;
        for (unsigned child = 0; child < 8; ++child) {
            const OctreeCube cell = child_cube(item.cell, child);
            if (node.has_child(child))
                todo.push_back({node.child_slot(child), cell, item.depth + 1});
            else
                visit(std::nullopt, cell, item.depth + 1);
        }
    }
}

inline bool triangle_meets_cell(const Triangle& tri, const OctreeCube& cell) {
    const Vec3d lo(cell.lo);
    return triangle_meets_box_by_clipping(tri, lo, lo + Vec3d(double(cell.size)));
}

/// The interval of the ray's whole line inside the closed box, in double; empty (enter > exit)
/// when the line misses it.
inline std::pair<double, double> line_interval(const Ray& ray, const Vec3d& lo, const Vec3d& hi) {
    double enter = -std::numeric_limits<double>::infinity(), exit = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 3; ++axis) {
        const double o = ray.origin[axis], d = ray.dir[axis];
        if (d == 0.0) {
            if (o < lo[axis] || o > hi[axis]) return {1.0, 0.0};
            continue;
        }
        double t0 = (lo[axis] - o) / d, t1 = (hi[axis] - o) / d;
        if (t0 > t1) std::swap(t0, t1);
        enter = std::max(enter, t0);
        exit = std::min(exit, t1);
    }
    return {enter, exit};
}

/// Rays that run along the octree's own planes: aimed at interior node centres, lying in a
/// node's centre plane (the direction component across it +0 or -0), and along the edge line
/// where two centre planes of a node meet, parallel to the third axis.
inline std::vector<Ray> rays_along_the_planes(const Octree& tree, std::uint32_t seed, std::size_t per_node) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> sym(-1.0f, 1.0f);
    std::vector<OctreeCube> interior;
    for_each_cell(tree, [&](std::optional<OctreeNode> node, const OctreeCube& cell, int) {
        if (node && !node->is_leaf()) interior.push_back(cell);
    });
    std::shuffle(interior.begin(), interior.end(), rng);
    interior.resize(std::min<std::size_t>(interior.size(), 60));
    const float reach = 4.0f * tree.cube().size;
    std::vector<Ray> rays;
    for (const OctreeCube& cell : interior) {
        const Vec3f mid = cell.mid();
        for (std::size_t i = 0; i < per_node; ++i) {
            Vec3f d = normalize(Vec3f{sym(rng), sym(rng), sym(rng)});
            rays.push_back({mid - d * reach, d});  // through the centre
            const int axis = int(rng() % 3);
            const float zero = (rng() & 1) ? 0.0f : -0.0f;
            d[axis] = zero;
            d = d / length(d);
            d[axis] = zero;
            Vec3f in_plane = mid + Vec3f{sym(rng), sym(rng), sym(rng)} * (0.5f * cell.size);
            in_plane[axis] = mid[axis];
            rays.push_back({in_plane - d * reach, d});  // in the centre plane across `axis`
            Vec3f along{zero, zero, zero};
            along[axis] = (rng() & 1) ? 1.0f : -1.0f;
            Vec3f on_edge = mid;
            on_edge[axis] -= along[axis] * reach;
            rays.push_back({on_edge, along});  // on the edge line of the two other centre planes
        }
    }
    return rays;
}

}  // namespace trident::testing
