// HugePageArray: large arrays get 2 MiB-aligned storage (what madvise needs to grant huge pages),
// small ones ordinary storage, and both behave as std::vector.
#include <doctest/doctest.h>

#include <cstdint>
#include <numeric>

#include "core/huge_page_array.h"

using namespace trident;

namespace {

bool aligned_to_huge_page(const void* p) {
    return reinterpret_cast<std::uintptr_t>(p) % HugePageAllocator<char>::kHugePageBytes == 0;
}

}  // namespace

TEST_CASE("a large array is aligned to a huge page and keeps its values through growth and copies") {
    constexpr std::size_t kCount = 3 * HugePageAllocator<std::uint32_t>::kHugePageBytes / sizeof(std::uint32_t) + 7;
    HugePageArray<std::uint32_t> values(kCount);
    CHECK(aligned_to_huge_page(values.data()));
    std::iota(values.begin(), values.end(), 0u);
    values.resize(2 * kCount, 5u);  // reallocates: old storage freed through the same allocator
    CHECK(aligned_to_huge_page(values.data()));
    const HugePageArray<std::uint32_t> copy = values;
    CHECK(aligned_to_huge_page(copy.data()));
    for (std::size_t i = 0; i < kCount; ++i) REQUIRE(copy[i] == i);
    for (std::size_t i = kCount; i < 2 * kCount; ++i) REQUIRE(copy[i] == 5u);
}

TEST_CASE("a small array takes ordinary storage and grows across the huge-page threshold") {
    HugePageArray<double> values;
    for (int i = 0; i < 600000; ++i) values.push_back(i * 0.5);  // 4.8 MB at the end
    CHECK(aligned_to_huge_page(values.data()));
    for (int i = 0; i < 600000; ++i) REQUIRE(values[std::size_t(i)] == i * 0.5);
    HugePageArray<double> small(10, 1.0);
    CHECK(small.size() == 10);
    CHECK(small[9] == 1.0);
    small.clear();
    small.shrink_to_fit();
    CHECK(small.empty());
}
