#pragma once
// Stable least-significant-digit radix sort by a 32-bit key: three passes of 11 bits. O(n), for the
// builder's large sorts (split-plane events, triangles in Morton order).
#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace trident::kd {

/// Sorts `items` by key(item), keeping the input order among equal keys. `scratch` must hold at
/// least as many items.
template <class T, class Key>
void radix_sort(std::span<T> items, std::span<T> scratch, Key key) {
    constexpr int kBits = 11, kBuckets = 1 << kBits, kPasses = 3;
    std::vector<std::uint32_t> counts(kPasses * kBuckets, 0);
    for (const T& item : items) {
        const std::uint32_t k = key(item);
        for (int pass = 0; pass < kPasses; ++pass) ++counts[pass * kBuckets + ((k >> (pass * kBits)) & (kBuckets - 1))];
    }
    std::span<T> from = items, to = scratch.first(items.size());
    for (int pass = 0; pass < kPasses; ++pass) {
        std::uint32_t* offsets = counts.data() + pass * kBuckets;
        std::uint32_t sum = 0;
        for (int b = 0; b < kBuckets; ++b) sum += std::exchange(offsets[b], sum);
        for (const T& item : from) to[offsets[(key(item) >> (pass * kBits)) & (kBuckets - 1)]++] = item;
        std::swap(from, to);
    }
    std::copy(from.begin(), from.end(), items.begin());  // odd pass count: the result is in scratch
}

}  // namespace trident::kd
