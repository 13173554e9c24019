// Mask helpers and the lane operations of Lanes<batch>, on every width this machine runs, against
// bit patterns and against Lanes<float> lane by lane.
#include <doctest/doctest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/ray.h"
#include "each_arch.h"
#include "simd/lanes.h"
#include "simd/mask.h"
#include "support/float_bits.h"

using namespace trident;
using trident::testing::bits_of;
using trident::testing::for_each_packet_arch;

namespace {

template <class Arch>
xsimd::batch_bool<float, Arch> mask_of(std::uint32_t pattern) {
    std::array<bool, xsimd::batch_bool<float, Arch>::size> lanes;
    for (std::size_t i = 0; i < lanes.size(); ++i) lanes[i] = (pattern >> i) & 1u;
    return xsimd::batch_bool<float, Arch>::load_unaligned(lanes.data());
}

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

/// Awkward values for lane operations: signed zeros, infinities, NaN, ties.
const std::vector<float> kSpecials = {0.0f,      -0.0f,      1.0f, -1.0f,  2.5f, -2.5f,
                                      kInfinity, -kInfinity, kNaN, 1e-40f, -3.0f};

}  // namespace

TEST_CASE("mask_bits and back, lane count, first lane and index select agree with every lane pattern") {
    for_each_packet_arch([]<class Arch>() {
        using Mask = xsimd::batch_bool<float, Arch>;
        using Ids = xsimd::batch<std::uint32_t, Arch>;
        constexpr std::size_t width = Mask::size;
        std::size_t wrong = 0;
        for (std::uint32_t pattern = 0; pattern < (1u << width); ++pattern) {
            const Mask mask = mask_of<Arch>(pattern);
            std::array<std::uint32_t, width> selected;
            simd::select_index(mask, Ids(7u), Ids(3u)).store_unaligned(selected.data());
            bool selects_right = true;
            for (std::size_t i = 0; i < width; ++i) selects_right &= selected[i] == ((pattern >> i) & 1u ? 7u : 3u);
            // The mask built from the bits, read lane by lane through a select.
            using Float = xsimd::batch<float, Arch>;
            std::array<float, width> from_bits;
            xsimd::select(simd::mask_from_bits<Arch>(pattern), Float(1.0f), Float(0.0f)).store_unaligned(from_bits.data());
            for (std::size_t i = 0; i < width; ++i) selects_right &= from_bits[i] == ((pattern >> i) & 1u ? 1.0f : 0.0f);
            const int first = pattern == 0 ? int(width) : std::countr_zero(pattern);
            if (simd::mask_bits(mask) != pattern || simd::active_lane_count(mask) != std::popcount(pattern) ||
                simd::first_active_lane(mask) != first || !selects_right)
                ++wrong;
        }
        CHECK(wrong == 0);
    });
}

TEST_CASE("horizontal_min finds the smallest lane and skips NaN lanes") {
    for_each_packet_arch([]<class Arch>() {
        using Float = xsimd::batch<float, Arch>;
        constexpr std::size_t width = Float::size;
        for (std::size_t smallest_at = 0; smallest_at < width; ++smallest_at) {
            std::array<float, width> lanes;
            for (std::size_t i = 0; i < width; ++i) lanes[i] = float(i % 3) + 1.0f;
            lanes[smallest_at] = -2.0f;
            lanes[(smallest_at + 1) % width] = kNaN;
            CHECK(simd::horizontal_min(Float::load_unaligned(lanes.data())) == -2.0f);
        }
        CHECK(simd::horizontal_min(Float(kNaN)) == kInfinity);
        // Random lanes with NaN and infinities mixed in, against the smallest non-NaN lane.
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> value(-1e6f, 1e6f);
        std::uniform_int_distribution<int> kind(0, 9);
        std::size_t wrong = 0;
        for (int trial = 0; trial < 500; ++trial) {
            std::array<float, width> lanes;
            float expected = kInfinity;
            for (float& lane : lanes) {
                const int k = kind(rng);
                lane = k == 0 ? kNaN : k == 1 ? kInfinity : k == 2 ? -kInfinity : value(rng);
                if (lane < expected) expected = lane;
            }
            wrong += simd::horizontal_min(Float::load_unaligned(lanes.data())) != expected;
        }
        CHECK(wrong == 0);
    });
}

TEST_CASE("Lanes of a batch select, min, max and abs lane by lane as Lanes<float> does, NaN and -0 included") {
    for_each_packet_arch([]<class Arch>() {
        using Float = xsimd::batch<float, Arch>;
        using L = Lanes<Float>;
        using S = Lanes<float>;
        constexpr std::size_t width = Float::size;
        std::size_t wrong = 0, compared = 0;
        for (const float b : kSpecials) {
            // a runs through the specials lane by lane, b is the same in every lane
            for (std::size_t start = 0; start < kSpecials.size(); start += width) {
                typename L::Array a{};
                std::array<bool, width> pick;
                for (std::size_t i = 0; i < width; ++i) {
                    a[i] = kSpecials[(start + i) % kSpecials.size()];
                    pick[i] = (start + i) % 2 == 0;
                }
                const Float va = L::from_array(a), vb(b);
                const auto mask = xsimd::batch_bool<float, Arch>::load_unaligned(pick.data());
                const auto mins = L::to_array(L::min(va, vb)), maxs = L::to_array(L::max(va, vb));
                const auto abss = L::to_array(L::abs(va)), sels = L::to_array(L::select(mask, va, vb));
                for (std::size_t i = 0; i < width; ++i) {
                    ++compared;
                    wrong += bits_of(mins[i]) != bits_of(S::min(a[i], b));
                    wrong += bits_of(maxs[i]) != bits_of(S::max(a[i], b));
                    wrong += bits_of(abss[i]) != bits_of(S::abs(a[i]));
                    wrong += bits_of(sels[i]) != bits_of(S::select(pick[i], a[i], b));
                }
            }
        }
        CHECK(compared >= kSpecials.size() * kSpecials.size());
        CHECK(wrong == 0);
    });
}

TEST_CASE("the watertight axis permutation of a batch matches the scalar one lane by lane, ties and signs included") {
    // Directions with every major axis, ties between axes, signed zeros and both signs.
    std::vector<Vec3f> dirs;
    const float values[] = {0.0f, -0.0f, 0.5f, -0.5f, 1.0f, -1.0f};
    for (const float x : values)
        for (const float y : values)
            for (const float z : values) dirs.push_back({x, y, z});
    const Vec3f probe{1.0f, 2.0f, 3.0f};
    for_each_packet_arch([&]<class Arch>() {
        using Float = xsimd::batch<float, Arch>;
        using L = Lanes<Float>;
        constexpr std::size_t width = Float::size;
        std::size_t wrong = 0;
        for (std::size_t first = 0; first < dirs.size(); first += width) {
            std::array<typename L::Array, 3> d{};
            for (std::size_t i = 0; i < width; ++i)
                for (int axis = 0; axis < 3; ++axis) d[axis][i] = dirs[(first + i) % dirs.size()][axis];
            const Vec3T<Float> dir(L::from_array(d[0]), L::from_array(d[1]), L::from_array(d[2]));
            const auto permutation = L::major_axis_to_z(dir);
            const Vec3T<Float> moved = permutation.apply(Vec3T<Float>(probe)), moved_dir = permutation.apply(dir);
            const auto mx = L::to_array(moved.x), my = L::to_array(moved.y), mz = L::to_array(moved.z);
            const auto dz = L::to_array(moved_dir.z);
            for (std::size_t i = 0; i < width; ++i) {
                const Vec3f& scalar_dir = dirs[(first + i) % dirs.size()];
                const auto scalar = Lanes<float>::major_axis_to_z(scalar_dir);
                const Vec3f expected = scalar.apply(probe);
                wrong += mx[i] != expected.x || my[i] != expected.y || mz[i] != expected.z;
                wrong += bits_of(dz[i]) != bits_of(scalar.apply(scalar_dir).z);
            }
        }
        CHECK(wrong == 0);
    });
}
