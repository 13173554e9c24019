#pragma once
// The binary SAH tree with spatial splits (Stich, Friedrich and Dietrich 2009, "Spatial splits in
// bounding volume hierarchies", the SBVH; Embree's high-quality builder does the same): at each
// node the best object split (the references' centroids in bins) competes with the best spatial
// split, a plane that cuts each triangle straddling it into a piece on each side. Where large
// triangles overlap (a wall across a room, the columns and arches of an atrium), object splits
// leave the children's boxes overlapping and a ray visits both; a spatial split makes them
// disjoint at the price of testing the cut triangles in two leaves. A leaf holds whole triangles
// (a piece's id), so the answers do not change, only which leaves test a triangle.
//
// Spatial splits are looked for only where the best object split's children overlap by more than
// kOverlapShare of the root's surface area (Stich et al.'s alpha), and the extra references a
// subtree may add are bounded by its share of the budget, so the tree stays within
// (1 + budget) references a triangle. Below the nodes where a spatial split may still be looked
// for, the subtrees are the binned builder's (binned_sah_splitter.h). Subtrees are built in
// parallel; every decision is made from a node's own references, so the tree does not depend on
// the number of threads.
#include "accel/bvh/bvh_node.h"
#include "accel/bvh/bvh_options.h"
#include "core/huge_page_array.h"
#include "core/mesh.h"
#include "core/ray.h"

namespace trident::bvh {

struct SpatialSplitTree {
    HugePageArray<BvhNode> nodes;        // depth-first, root first, as TreeBuilder's
    HugePageArray<TriangleId> leaf_ids;  // leaves' triangles in leaf order; a cut triangle in each of its leaves
};

/// Builds with oneTBB on the caller's threads. `options`: the SAH costs, max_leaf_size and
/// spatial_split_budget; the bin counts where spatial splits are looked for are the builder's own,
/// below them the options' (the binned builder's).
SpatialSplitTree build_with_spatial_splits(const Mesh& mesh, const BvhOptions& options);

}  // namespace trident::bvh
