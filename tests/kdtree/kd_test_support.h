#pragma once
// What the kd-tree tests need beyond tests/support: the cells of a built tree, its split planes,
// scenes whose triangles lie in split planes, and the built-in scenes with their trees.
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "accel/kdtree/kdtree.h"
#include "core/aabb.h"
#include "core/mesh.h"
#include "core/scene.h"
#include "scenes/builtin.h"

namespace trident::testing {

struct KdCell {
    std::uint32_t node;
    Aabb cell;
    int depth;
};

/// Every node of the tree with its cell, parents before children.
inline std::vector<KdCell> kd_cells(const KdTree& tree) {
    std::vector<KdCell> out;
    if (tree.nodes().empty()) return out;
    out.push_back({0, tree.bounds(), 0});
    for (std::size_t i = 0; i < out.size(); ++i) {
        const KdCell item = out[i];
        const KdNode& node = tree.nodes()[item.node];
        if (node.is_leaf()) continue;
        KdCell below{node.below_child(), item.cell, item.depth + 1},
            above{node.above_child(), item.cell, item.depth + 1};
        below.cell.hi[node.axis()] = node.split();
        above.cell.lo[node.axis()] = node.split();
        out.push_back(below);
        out.push_back(above);
    }
    return out;
}

struct SplitPlane {
    int axis;
    float position;
    Aabb cell;  // the cell of the node it splits
};

inline std::vector<SplitPlane> kd_split_planes(const KdTree& tree) {
    std::vector<SplitPlane> out;
    for (const KdCell& c : kd_cells(tree)) {
        const KdNode& node = tree.nodes()[c.node];
        if (!node.is_leaf()) out.push_back({node.axis(), node.split(), c.cell});
    }
    return out;
}

/// Axis-aligned boxes with corners on a coarse integer grid, each face two triangles: many
/// triangles lie in the same planes, which the SAH picks as split planes, and the box edges lie
/// in them too.
inline Mesh grid_boxes(std::size_t count, std::uint32_t seed, int grid = 8) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> corner(0, grid - 1), size(1, 3);
    Mesh mesh;
    for (std::size_t b = 0; b < count; ++b) {
        const Vec3f lo{float(corner(rng)), float(corner(rng)), float(corner(rng))};
        const Vec3f hi = lo + Vec3f{float(size(rng)), float(size(rng)), float(size(rng))};
        std::uint32_t v[8];
        for (int i = 0; i < 8; ++i)
            v[i] = mesh.add_vertex({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
        const int faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
        for (const auto& f : faces) {
            mesh.add_triangle(v[f[0]], v[f[1]], v[f[2]]);
            mesh.add_triangle(v[f[0]], v[f[2]], v[f[3]]);
        }
    }
    return mesh;
}

/// A built-in scene and its kd-tree (default options), each made once per test run: several test
/// cases trace the big ones, and building them dominates the run time.
struct BuiltinKd {
    Scene scene;
    KdTree tree;
};
inline const BuiltinKd& builtin_kd(const std::string& name) {
    static std::map<std::string, BuiltinKd> cache;
    auto it = cache.find(name);
    if (it == cache.end()) {
        Scene scene = make_builtin_scene(name);
        KdTree tree = KdTree::build(scene.mesh);
        it = cache.emplace(name, BuiltinKd{std::move(scene), std::move(tree)}).first;
    }
    return it->second;
}

}  // namespace trident::testing
