#pragma once
// One ray against all Width child boxes of a wide node in one vector step (Embree's
// node_intersector1.h): the slab test of core/slab_test.h over a batch with one box per lane and
// the ray in every lane. The near and far planes of each axis are picked once per ray from the
// direction's sign (the rows of WideNode), so a node costs three loads of each, six differences,
// six products and the reductions.
//
// Robust: Ize's widening of the far distances, and the zero offsets left to min and max, which
// return their second operand for NaN (core/slab_test.h, clip_to_ordered_slab). Fast: the same
// without the widening. Either way an unused slot's empty box [+inf, -inf] has its near plane at
// +inf along the ray, so no ray enters it.
//
// The walk waits on this test node after node (the next node's address comes out of it), so it is
// written for a short chain rather than as three clip_to_ordered_slab steps: Ize's widening is
// folded into a second reciprocal once per ray (his inv_dir_pad), which takes its product off the
// chain, and entry and exit are reduced in pairs. The folded factor is still enough: a far distance
// carries four roundings either way (the reciprocal, the difference, the product, and the factor's
// product with one or the other). NaN keeps its rule for x, paired with t_min; a NaN in y or z also
// drops the other slab of their pair: a looser, still conservative, test for an origin exactly on a
// plane the ray runs along.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <xsimd/xsimd.hpp>

#include "accel/bvh/wide_node.h"
#include "core/ray.h"
#include "core/slab_test.h"
#include "simd/lanes.h"
#include "simd/mask.h"

namespace trident::bvh {

/// Ray extents are prune-tested against the closest hit widened by this factor, so that a box
/// whose entry rounds a few ulps past a hit at the same distance is still visited: whichever order
/// the children are visited in (by one ray or by a packet), every triangle hit at the closest t is
/// tested and the lowest id among them is kept (wide_bvh.h), so the answer does not depend on the
/// order.
inline constexpr float kPruneSlack = 1.0f + 0x1p-20f;

/// The largest t a box may be entered at to still hold a hit for a ray whose closest so far is t.
template <class T>
T prune_limit(const T& t_closest) {
    return t_closest * T(kPruneSlack);
}

/// A node's Width slots as the widest batches the file's instruction set has: one batch of Width
/// where it holds one (8 slots on AVX2 and above), else Width / kChunk batches (the portable
/// build's baseline, SSE4.2, tests an 8-wide node as two halves). Either way each slot sees the
/// same operations, so the answer is the same bits.
template <std::size_t Width>
inline constexpr std::size_t kNodeChunk = std::min(Width, xsimd::batch<float>::size);

/// Chunk is a template parameter, defaulted from the file's instruction set, so that the test's
/// layout is in its name: WideBoxTest<8, S, 4> (two SSE halves, the portable baseline) and
/// WideBoxTest<8, S, 8> (one AVX2 step, a kernel file) are two types. With one name for both, the
/// linker kept one copy of each member for every file, and a baseline caller's 4-wide object was
/// written by an 8-wide constructor (a stack overflow the portable sanitizer build found).
template <std::size_t Width, SlabTest Slabs, std::size_t Chunk = kNodeChunk<Width>>
class WideBoxTest {
public:
    using Float = xsimd::make_sized_batch_t<float, Chunk>;
    static constexpr std::size_t kChunk = Chunk;
    static_assert(Float::size == kChunk && Width % kChunk == 0, "no vector of this width on the target");

    explicit WideBoxTest(const Ray& ray) {
        for (int axis = 0; axis < 3; ++axis) {
            const float inv_dir = 1.0f / ray.dir[axis];  // +-inf for +-0
            origin_[axis] = Float(ray.origin[axis]);
            inv_dir_[axis] = Float(inv_dir);
            inv_dir_far_[axis] = Float(Slabs == SlabTest::robust ? inv_dir * detail::kFarScale : inv_dir);
            const bool negative = inv_dir < 0.0f;
            near_row_[axis] = near_row(axis, negative);
            far_row_[axis] = far_row(axis, negative);
        }
    }

    /// Bit k set when child k's box meets [t_min, t_max]; its entry distance in t_entry[k].
    std::uint32_t enter(const WideNode<Width>& node, float t_min, float t_max,
                        std::array<float, Width>& t_entry) const {
        using L = Lanes<Float>;
        std::uint32_t entered = 0;
        for (std::size_t first = 0; first < Width; first += kChunk) {
            const auto near = [&](int axis) {
                return (Float::load_aligned(node.bounds[near_row_[axis]] + first) - origin_[axis]) * inv_dir_[axis];
            };
            const auto far = [&](int axis) {
                return (Float::load_aligned(node.bounds[far_row_[axis]] + first) - origin_[axis]) * inv_dir_far_[axis];
            };
            const Float entry = L::max(L::max(near(1), near(2)), L::max(near(0), Float(t_min)));
            const Float exit = L::min(L::min(far(1), far(2)), L::min(far(0), Float(t_max)));
            entry.store_unaligned(t_entry.data() + first);
            entered |= simd::mask_bits(entry <= exit) << first;
        }
        return entered;
    }

private:
    Float origin_[3], inv_dir_[3], inv_dir_far_[3];
    int near_row_[3], far_row_[3];
};

}  // namespace trident::bvh
