#pragma once
// The pyramid of an image tile's primary rays, for skipping tiles whose rays all miss
// (Reshetov, Soupikov and Hurley 2005, "Multi-level ray tracing algorithm": a tile's frustum
// tested against the top of the tree before any of its rays is made). On the study's scans and
// Teapot two thirds or more of the image's 16x16 tiles see only the background; each of their
// packets used to be made, set up and tested against the root, as Embree's packet calls still are.
//
// The test is done in double on the exact rays through the tile's corners, whose cone holds every
// exact ray of the tile (a pixel's unnormalized direction is affine in its column and row, and
// normalizing only scales it). The rays actually traced are those rays rounded to float
// (a few float ulps of each direction component, Camera::primary_direction), which the tests'
// margin covers many times over, so a tile is skipped only where none of its traced rays can
// enter the boxes: the same misses as tracing it.
#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "accel/bvh/wide_node.h"
#include "camera/camera.h"
#include "core/aabb.h"
#include "core/vec3.h"
#include "render/image_tiles.h"

namespace trident {

/// The pyramid of one tile's primary rays: from the eye, a side plane through the rays of each
/// pair of adjacent corners of the tile's outer edge.
class TileFrustum {
public:
    TileFrustum(const Camera& camera, const ImageTile& tile) : eye_(Vec3d(camera.eye())) {
        // The tile's outer edges, half a pixel beyond its outer pixels' centres, so that even a
        // tile one pixel wide spans a pyramid (through the centres alone its sides would be flat).
        const double left = tile.x0 - 0.5, right = tile.x1 - 0.5, top = tile.y0 - 0.5, bottom = tile.y1 - 0.5;
        // Corners in turn around the tile, so that consecutive ones span a side plane.
        const std::array<Vec3d, 4> corner{camera.direction_in_double(left, top), camera.direction_in_double(right, top),
                                          camera.direction_in_double(right, bottom),
                                          camera.direction_in_double(left, bottom)};
        const Vec3d inside = corner[0] + corner[1] + corner[2] + corner[3];
        for (int k = 0; k < 4; ++k) {
            Vec3d n = cross(corner[k], corner[(k + 1) % 4]);
            if (dot(n, inside) < 0.0) n = -n;
            normal_[k] = n;
            normal_length_[k] = length(n);
        }
    }

    /// False only where the box [lo, hi] lies outside one side plane by more than `margin`, a
    /// distance: no point of the box is within `margin` of the pyramid.
    bool may_reach(const Vec3d& lo, const Vec3d& hi, double margin) const {
        for (int k = 0; k < 4; ++k) {
            const Vec3d& n = normal_[k];
            // The box's corner farthest along n, the plane's inside.
            const Vec3d p(n.x >= 0.0 ? hi.x : lo.x, n.y >= 0.0 ? hi.y : lo.y, n.z >= 0.0 ? hi.z : lo.z);
            if (dot(n, p - eye_) < -margin * normal_length_[k]) return false;
        }
        return true;
    }

private:
    Vec3d eye_;
    std::array<Vec3d, 4> normal_;
    std::array<double, 4> normal_length_;
};

/// Which tiles of a camera's image may hit a structure: those whose pyramid (TileFrustum) reaches
/// one of the boxes a primary ray must enter to hit it, in double, the largest first. For the wide
/// BVH they are its root's children and, below each inner one, that node's children: a tile that
/// reaches a child but none of its children is culled too (of Teapot's 1920x1080 image that culls
/// 0.54 of the tiles, where the root's children alone cull 0.40; 0.65 see nothing). For the other
/// structures it is the root's box (the binary BVH's root node, the KD-tree's root cell, the
/// octree's cube). A structure with none of these (the brute force) has no bounds, and every tile
/// may hit it.
class TileCuller {
public:
    template <class Structure>
    TileCuller(const Structure& structure, const Camera& camera) : camera_(camera) {
        if constexpr (requires { structure.node_at(structure.nodes()[0].child[0]); }) {
            const auto nodes = structure.nodes();
            if (nodes.empty()) return;
            using Node = typename decltype(nodes)::value_type;
            // Child k's box, appended to `out` unless empty.
            const auto add_child = [](const Node& node, std::size_t k, std::vector<Box>& out) {
                const auto corner = [&](int (*row)(int)) {
                    return Vec3d(node.bounds[row(0)][k], node.bounds[row(1)][k], node.bounds[row(2)][k]);
                };
                return add(out, corner(bvh::lower_row), corner(bvh::upper_row));
            };
            const Node& root = nodes[0];
            for (std::size_t k = 0; k < root.width && !root.child[k].is_empty(); ++k) {
                if (!add_child(root, k, boxes_) || root.child[k].is_leaf()) continue;
                const Node& child = structure.node_at(root.child[k]);
                Box& box = boxes_.back();
                box.first_below = below_.size();
                for (std::size_t j = 0; j < child.width && !child.child[j].is_empty(); ++j) add_child(child, j, below_);
                box.below_count = below_.size() - box.first_below;
                std::sort(below_.begin() + std::ptrdiff_t(box.first_below), below_.end(), by_area);
            }
        } else if constexpr (requires { structure.nodes()[0].bounds; }) {
            if (!structure.nodes().empty())
                add(boxes_, Vec3d(structure.nodes()[0].bounds.lo), Vec3d(structure.nodes()[0].bounds.hi));
        } else if constexpr (requires { structure.bounds().lo; }) {
            add(boxes_, Vec3d(structure.bounds().lo), Vec3d(structure.bounds().hi));
        } else if constexpr (requires { structure.cube().size; }) {
            const Vec3d lo(structure.cube().lo);
            add(boxes_, lo, lo + Vec3d(double(structure.cube().size)));
        } else {
            bounded_ = false;
        }
        std::sort(boxes_.begin(), boxes_.end(), by_area);
        // How far a traced ray may stray from the exact pyramid within the boxes: float directions
        // are off by under 1e-6 of their length and the robust slab test widens a box by 1e-7 of
        // t, so 1e-5 of the farthest box corner's distance from the eye; and 1e-6 of the largest
        // coordinate for boxes whose float corners were rounded (the octree's cube). The boxes
        // below lie inside these.
        const Vec3d eye(camera.eye());
        double reach = 0.0, largest = 0.0;
        for (const Box& box : boxes_)
            for (int axis = 0; axis < 3; ++axis) {
                reach = std::max({reach, std::abs(box.lo[axis] - eye[axis]), std::abs(box.hi[axis] - eye[axis])});
                largest = std::max({largest, std::abs(box.lo[axis]), std::abs(box.hi[axis])});
            }
        margin_ = std::sqrt(3.0) * (1e-5 * reach + 1e-6 * largest);
    }

    /// Whether some primary ray of `tile` may hit the structure: false only where none of the
    /// tile's rays, as traced, can enter the boxes.
    bool may_hit(const ImageTile& tile) const;

private:
    struct Box {
        Vec3d lo, hi;
        double area;
        std::size_t first_below = 0, below_count = 0;  // its children's boxes in below_, if any
    };
    /// Appends the box [lo, hi] unless it is empty; returns whether it did.
    static bool add(std::vector<Box>& boxes, const Vec3d& lo, const Vec3d& hi) {
        if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z) || !is_finite(lo) || !is_finite(hi)) return false;
        const Vec3d size = hi - lo;
        boxes.push_back({lo, hi, size.x * size.y + size.y * size.z + size.z * size.x, 0, 0});
        return true;
    }
    /// The largest first: where most tiles reach the scene (an interior), the first test says so.
    static bool by_area(const Box& a, const Box& b) { return a.area > b.area; }

    const Camera& camera_;
    std::vector<Box> boxes_, below_;
    double margin_ = 0.0;
    bool bounded_ = true;
};

inline bool TileCuller::may_hit(const ImageTile& tile) const {
    if (!bounded_) return true;
    if (boxes_.empty()) return false;
    const TileFrustum frustum(camera_, tile);
    const auto reaches = [&](const Box& box) { return frustum.may_reach(box.lo, box.hi, margin_); };
    for (const Box& box : boxes_) {
        if (!reaches(box)) continue;
        if (box.below_count == 0) return true;
        const auto below = std::span(below_).subspan(box.first_below, box.below_count);
        if (std::any_of(below.begin(), below.end(), reaches)) return true;
    }
    return false;
}

}  // namespace trident
