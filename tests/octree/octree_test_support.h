#pragma once
// Independent checks for the octree tests: exact cells walked from the root, triangle/box
// overlap by clipping (a different algorithm from the builder's separating axes), slab
// intervals in double.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "accel/octree/octree.h"

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

/// Does the triangle meet the closed box [lo, hi]? Clips the triangle (Sutherland-Hodgman) against
/// the six faces in double; touching counts.
inline bool triangle_meets_box_by_clipping(const Triangle& tri, const Vec3d& lo, const Vec3d& hi) {
    std::vector<Vec3d> polygon{Vec3d(tri.a), Vec3d(tri.b), Vec3d(tri.c)}, next;
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            const double bound = side == 0 ? lo[axis] : hi[axis];
            auto inside = [&](const Vec3d& p) { return side == 0 ? p[axis] >= bound : p[axis] <= bound; };
            next.clear();
            for (std::size_t i = 0; i < polygon.size(); ++i) {
                const Vec3d& p = polygon[i];
                const Vec3d& q = polygon[(i + 1) % polygon.size()];
                if (inside(p)) next.push_back(p);
                if (inside(p) != inside(q)) {
                    const double t = (bound - p[axis]) / (q[axis] - p[axis]);
                    Vec3d x = p + (q - p) * t;
                    x[axis] = bound;
                    next.push_back(x);
                }
            }
            polygon.swap(next);
            if (polygon.empty()) return false;
        }
    }
    return true;
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

}  // namespace trident::testing
