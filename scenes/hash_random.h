#pragma once
// Portable deterministic randomness for the procedural scenes. std::mt19937 is portable but the
// standard distributions are not (libstdc++ and libc++ turn the same bits into different floats),
// so scenes draw from splitmix64 (Steele, Lea and Flood, "Fast splittable pseudorandom number
// generators", OOPSLA 2014) and do their own arithmetic on the bits. Hashing a key instead of
// advancing a shared state also lets parallel code draw the same numbers in any order.
#include <cstdint>

namespace trident {

constexpr std::uint64_t splitmix64(std::uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

/// Hash of a key made of several integers (a lattice point, an object index and a stream...).
constexpr std::uint64_t hash_combine(std::uint64_t seed, std::uint64_t value) {
    return splitmix64(seed ^ splitmix64(value));
}

/// The top 24 bits as a float in [0, 1): every value exactly representable, no rounding up to 1.
constexpr float unit_float(std::uint64_t bits) { return float(bits >> 40) * (1.0f / 16777216.0f); }

/// A sequential stream: draw i is splitmix64 of (seed, i), so a stream is cheap to fork per object.
class HashRandom {
public:
    explicit constexpr HashRandom(std::uint64_t seed) : seed_(splitmix64(seed)) {}

    constexpr std::uint64_t next_bits() { return hash_combine(seed_, counter_++); }
    /// Uniform in [0, 1).
    constexpr float uniform() { return unit_float(next_bits()); }
    /// Uniform in [lo, hi).
    constexpr float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
    /// Uniform integer in [0, n) for n > 0 (the 32-bit multiply-shift of Lemire, 2019; its bias is
    /// below 2^-32 * n and does not matter for scenery).
    constexpr std::uint32_t below(std::uint32_t n) {
        return std::uint32_t((std::uint64_t(std::uint32_t(next_bits() >> 32)) * n) >> 32);
    }

private:
    std::uint64_t seed_;
    std::uint64_t counter_ = 0;
};

}  // namespace trident
