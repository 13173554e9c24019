#pragma once
// Building the octree: the root cube is the scene's box made a cube; a node is split by the three
// planes through its centre into 8 children until it holds few enough triangles or reaches the
// maximum depth; a triangle goes to every child it overlaps. The result is already flattened
// (octree_node.h). Triangles with non-finite corners are left out (and reported).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "accel/octree/octree_node.h"
#include "core/mesh.h"

namespace trident {

inline constexpr int kOctreeMaxDepth = 12;

/// Which children a triangle is referenced by.
enum class OctreeOverlap {
    triangle,      // the children the triangle itself overlaps (separating-axis test)
    bounding_box,  // the children its bounding box overlaps (the reference study's rule)
};

struct OctreeOptions {
    /// Deepest level a leaf may sit at (the root is level 0), 1 to kOctreeMaxDepth; 0 chooses
    /// default_octree_depth().
    int max_depth = 0;
    /// A node holding this many triangles or fewer is a leaf.
    std::size_t min_primitives = 1;
    OctreeOverlap overlap = OctreeOverlap::triangle;
    /// Guard on the references all leaves hold together (memory), 0 meaning 64 N + 2^20: a node
    /// whose children would take the tree above it stays a leaf, and the build says so in its
    /// warning. Capped at 2^32 - 1 (32-bit offsets).
    std::size_t max_references = 0;
};

/// Throws std::invalid_argument naming the option when one is out of range.
void validate(const OctreeOptions& options);

/// The root cube: the box of the triangles made a cube on its lower corner, padded by a hair so
/// no triangle lies on the cube's outer faces.
OctreeCube octree_root_cube(std::span<const Triangle> triangles);

/// The maximum depth used when the options leave it at 0: the shallowest depth at which the
/// cells holding triangle centroids hold 10 triangles or fewer on average, clamped to [1, 9].
/// It reads the triangle count and the scene's extent (the cells are the cube's) through the
/// Morton keys the build sorts anyway, and follows where triangles crowd rather than how large
/// they are. On the built-in scenes: teapot 5, asteroid 7, hall 8, city 9; on the benchmark
/// scenes: Teapot 5, Bunny 7, Sponza, Dragon, Gallery and Buddha 8, Room 9 (its clusters of tiny
/// triangles would ask for more). Each traces within ~10% of its fastest depth, without the
/// deeper trees' 2-3 times longer builds. The reference study fixed 5 for the Teapot, 7 for
/// Sponza and 8 for the rest. The build then lowers it where cells would shrink towards the
/// coordinates' rounding (small meshes far from the origin).
int default_octree_depth(std::span<const std::uint32_t> sorted_morton_keys);

/// Counted while building; deterministic whatever the thread count.
struct OctreeBuildTotals {
    std::size_t nodes = 0;           // stored nodes
    std::size_t leaves = 0;          // stored leaves (the root, when it is one, even if empty)
    std::size_t empty_children = 0;  // children of interior nodes that overlap no triangle (not stored)
    std::size_t references = 0;      // triangle references held by the leaves
    std::size_t max_leaf_size = 0;
    std::size_t depth = 0;         // deepest leaf
    std::size_t budget_stops = 0;  // nodes left unsplit by the reference guard
    /// Traversal cost 1 per interior node and intersection cost 1 per reference, each weighted by
    /// the node's surface area relative to the root's (4^-depth for cubes).
    double sah_cost = 0.0;
};

struct OctreeLayout {
    OctreeCube cube;
    int max_depth = 0;                            // the limit used (after the default rule)
    std::vector<OctreeNode> nodes;                // nodes[0] is the root
    std::vector<std::uint32_t> triangle_indices;  // leaves' triangles: positions in `triangles`
    std::vector<Triangle> triangles;              // the finite triangles in Morton order (morton_order.h)
    std::vector<TriangleId> triangle_ids;         // file-order index of each of `triangles`
    OctreeBuildTotals totals;
    std::string warning;  // empty unless the builder had to give up something
};

/// Builds level by level, in parallel with oneTBB over the references and the nodes of a level;
/// which nodes split is decided in level order, so the arrays are the same whatever the thread
/// count. The reference guard is global: a node splits only while the references its children
/// add keep the whole tree within max_references (nodes earlier in the level come first).
OctreeLayout build_octree_layout(std::span<const Triangle> triangles, const OctreeOptions& options = {});

}  // namespace trident
