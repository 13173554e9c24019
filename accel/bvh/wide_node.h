#pragma once
// The wide BVH's layouts (Wald, Benthin and Boulos 2008, "Getting rid of packets"; Embree's
// bvh_node_aabb.h): a node holds up to Width children, their boxes stored by coordinate so that one
// ray tests all of them in one vector step, and a leaf is a run of triangle blocks of BlockSize
// triangles stored by coordinate, tested against one ray in one vector step (triangle_block.h).
#include <cstddef>
#include <cstdint>
#include <limits>

namespace trident::bvh {

/// A reference to a wide node's child: an interior node's byte offset in the node array, or a
/// leaf's run of blocks with the number of triangles it holds (for the counters and statistics: a
/// leaf's last block is padded with copies of its last triangle). empty() fills the unused slots
/// of a node. An offset rather than an index: the walk goes from node to node by loading a child's
/// reference and then the child, and an index would put a multiplication by the node's size
/// between the two loads, on the chain of dependent loads the walk waits on (Embree's references
/// are pointers).
class ChildRef {
public:
    static constexpr std::uint32_t kLeafBit = 1u << 31;
    static constexpr int kCountShift = 23;
    static constexpr std::uint32_t kMaxLeafTriangles = 255;
    static constexpr std::uint32_t kMaxFirstBlock = (1u << kCountShift) - 1;
    static constexpr std::uint32_t kMaxNodeOffset = kLeafBit - 1;

    ChildRef() = default;  // uninitialized, for stacks
    static constexpr ChildRef node_at(std::uint32_t byte_offset) { return ChildRef(byte_offset); }
    static constexpr ChildRef leaf(std::uint32_t first_block, std::uint32_t triangle_count) {
        return ChildRef(kLeafBit | triangle_count << kCountShift | first_block);
    }
    static constexpr ChildRef empty() { return ChildRef(std::numeric_limits<std::uint32_t>::max()); }

    constexpr bool is_leaf() const { return (bits_ & kLeafBit) != 0; }
    constexpr bool is_empty() const { return bits_ == empty().bits_; }
    constexpr std::uint32_t node_offset() const { return bits_; }
    constexpr std::uint32_t first_block() const { return bits_ & kMaxFirstBlock; }
    constexpr std::uint32_t triangle_count() const { return (bits_ & ~kLeafBit) >> kCountShift; }
    /// Blocks of the leaf: its triangles, rounded up to whole blocks.
    template <std::size_t BlockSize>
    constexpr std::uint32_t block_count() const {
        return (triangle_count() + BlockSize - 1) / BlockSize;
    }
    constexpr std::uint32_t bits() const { return bits_; }
    constexpr bool operator==(const ChildRef&) const = default;

private:
    explicit constexpr ChildRef(std::uint32_t bits) : bits_(bits) {}
    std::uint32_t bits_;
};
static_assert(sizeof(ChildRef) == 4);

/// Which bounds[] row holds an axis's lower or upper planes.
constexpr int lower_row(int axis) { return 2 * axis; }
constexpr int upper_row(int axis) { return 2 * axis + 1; }
/// The rows of the planes a ray meets first and last along an axis, by its direction's sign there.
constexpr int near_row(int axis, bool negative) { return negative ? upper_row(axis) : lower_row(axis); }
constexpr int far_row(int axis, bool negative) { return negative ? lower_row(axis) : upper_row(axis); }

/// Width children: bounds[lower_row(a)][i] and bounds[upper_row(a)][i] are child i's box along axis
/// a (lower_x, upper_x, lower_y, ... of Embree's node). An unused slot holds the empty box
/// [+inf, -inf], which no ray enters, and ChildRef::empty().
template <std::size_t Width>
struct alignas(Width * sizeof(float)) WideNode {
    static constexpr std::size_t width = Width;
    float bounds[6][Width];
    ChildRef child[Width];
};
static_assert(sizeof(WideNode<4>) == 112, "4 children: six rows of four floats and four references");
static_assert(sizeof(WideNode<8>) == 224, "8 children: six rows of eight floats and eight references");
static_assert(sizeof(WideNode<16>) == 448, "16 children: six rows of sixteen floats and sixteen references");

/// BlockSize triangles by coordinate: corner a's x of triangle i is a[0][i]. The corners are the
/// mesh's floats, untouched: the watertight test shears them per ray, so there is nothing to
/// precompute that would keep its results bit for bit. Lanes past a leaf's last triangle repeat it
/// (same corners, same id), so they find nothing the real lane does not.
template <std::size_t BlockSize>
struct alignas(BlockSize * sizeof(float)) TriangleBlock {
    static constexpr std::size_t size = BlockSize;
    float a[3][BlockSize], b[3][BlockSize], c[3][BlockSize];
    std::uint32_t id[BlockSize];  // file-order triangle ids
};
static_assert(sizeof(TriangleBlock<4>) == 160, "4 triangles: 36 floats and 4 ids");
static_assert(sizeof(TriangleBlock<8>) == 320, "8 triangles: 72 floats and 8 ids");

}  // namespace trident::bvh
