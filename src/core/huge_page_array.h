#pragma once
// Arrays a build writes once and traversal reads at random (nodes, triangle copies, build
// references), backed by 2 MiB pages where the kernel grants them.
//
// Why: a build of a million triangles touches over 100 MiB of fresh memory. In 4 KiB pages that
// is some 30,000 page faults, each a trip into the kernel, which took 11-14% of a one-thread
// build's samples; Linux's default transparent huge page mode ("madvise") grants 2 MiB pages only
// to memory that asks for them. Asking made the BVH's one-thread builds of the million-triangle
// scenes 2-8% faster (medians, bench/experiments/bvh-build.md); traversal speed did not change. Only arrays
// that will be filled should ask: the KD-tree's scratch blocks, sized for what may follow, built
// slower and less evenly with huge pages, as the kernel clears a whole 2 MiB page at the first
// touch. Small arrays, and systems without madvise, get ordinary memory.
#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace trident {

template <class T>
struct HugePageAllocator {
    using value_type = T;
    /// Below this an array takes ordinary memory: a 2 MiB page would be mostly empty.
    static constexpr std::size_t kHugePageBytes = std::size_t(2) << 20;

    HugePageAllocator() = default;
    template <class U>
    HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

    T* allocate(std::size_t count) {
        if (count > std::size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
        const std::size_t bytes = count * sizeof(T);
        if (bytes < kHugePageBytes) return std::allocator<T>().allocate(count);
        const std::size_t rounded = (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
        void* memory = std::aligned_alloc(kHugePageBytes, rounded);
        if (memory == nullptr) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        madvise(memory, rounded, MADV_HUGEPAGE);  // advice only: refused, the memory is still good
#endif
        return static_cast<T*>(memory);
    }
    void deallocate(T* memory, std::size_t count) noexcept {
        if (count * sizeof(T) < kHugePageBytes)
            std::allocator<T>().deallocate(memory, count);
        else
            std::free(memory);
    }

    template <class U>
    bool operator==(const HugePageAllocator<U>&) const noexcept {
        return true;
    }
};

/// A std::vector whose storage is HugePageAllocator's.
template <class T>
using HugePageArray = std::vector<T, HugePageAllocator<T>>;

}  // namespace trident
