#pragma once
// What BvhBuilder::automatic builds for the wide BVH: the tree with spatial splits where it is
// the better one, the binned tree elsewhere, judged by SAH.
//
// Why per mesh: spatial splits pay where large triangles overlap (walls, floors and columns among
// small detail), on Sponza 7% less SAH and every ray kind faster; on the scanned meshes, whose
// triangles are all tiny against the scene, the tree does not change and the build takes 2.5-3x
// as long; and on Room, of large triangles too, the greedy choice of spatial splits near the root
// left a tree of 4% more SAH whose rays were slower (bench/experiments/bvh-build.md). So a mesh
// with large triangles gets both trees, and the spatial one is kept where its SAH is lower; a
// mesh without them gets the binned tree alone. The binary BVH, the study's, is always binned.
#include "accel/bvh/bvh_options.h"
#include "core/mesh.h"

namespace trident::bvh {

/// A triangle is large when its box's surface area exceeds this share of the scene box's. On the
/// study's scans none is; on Teapot, Sponza, Room and Gallery such triangles hold 42-99% of the
/// summed box areas.
inline constexpr double kLargeTriangleArea = 1e-4;
/// Spatial splits are tried where the large triangles hold at least this share of the summed
/// box areas.
inline constexpr double kLargeTrianglesShare = 0.1;
/// The tree with spatial splits is kept where its SAH is below this share of the binned tree's:
/// a gain within 1% (Teapot's 0.3%) does not pay for the cut triangles' references.
inline constexpr double kSpatialSahShare = 0.99;

/// The share of the triangles' summed box areas that large ones hold, in [0, 1]; 0 for an empty
/// or flat-boxed mesh. Summed in fixed chunks in a fixed order, so it does not depend on the
/// number of threads.
double large_triangle_share(const Mesh& mesh);

/// Whether BvhBuilder::automatic builds the tree with spatial splits for this mesh (and the binned
/// one beside it): where large_triangle_share() is at least kLargeTrianglesShare.
inline bool tries_spatial_splits(const Mesh& mesh) { return large_triangle_share(mesh) >= kLargeTrianglesShare; }

/// With both trees built: whether the one with spatial splits is kept.
inline bool spatial_tree_pays(double spatial_sah, double binned_sah) { return spatial_sah < kSpatialSahShare * binned_sah; }

}  // namespace trident::bvh
