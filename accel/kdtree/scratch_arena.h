#pragma once
// A last-in-first-out scratch allocator. The kd-tree builder takes a mark before splitting a node
// and releases back to it once both children are built, so the millions of small event lists near
// the leaves cost no heap traffic. Blocks are kept for reuse until the arena dies. One arena per
// thread: a task that runs on a thread while another waits there is nested inside it and
// releases its memory before returning, so the last-in-first-out order holds.
//
// Blocks are 2 MiB aligned and asked for as transparent huge pages: a build writes a hundred MiB
// or more of fresh event lists, and faulting that in 4 KiB pages cost about a tenth of the
// Buddha's one-thread build (bench/RESULTS.md).
#include <algorithm>
#include <cstddef>
#include <memory>
#include <new>
#include <span>
#include <type_traits>
#include <vector>

#ifdef __linux__
#include <sys/mman.h>
#endif

namespace trident::kd {

class ScratchArena {
public:
    struct Mark {
        std::size_t block, offset;
    };

    Mark mark() const { return {current_, offset_}; }
    /// Frees everything allocated since `m` was taken.
    void release(Mark m) {
        current_ = m.block;
        offset_ = m.offset;
    }

    /// Uninitialized storage for `count` values of a trivial type.
    template <class T>
    std::span<T> allocate(std::size_t count) {
        static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);
        static_assert(alignof(T) <= kAlign);
        return {reinterpret_cast<T*>(allocate_bytes(count * sizeof(T))), count};
    }

private:
    static constexpr std::size_t kAlign = 16, kMinBlockBytes = std::size_t(1) << 20;

    struct FreeBlock {
        void operator()(std::byte* p) const { ::operator delete[](p, std::align_val_t(kHugePage)); }
    };
    struct Block {
        std::unique_ptr<std::byte[], FreeBlock> data;
        std::size_t bytes;
    };

    static constexpr std::size_t kHugePage = std::size_t(1) << 21;

    /// `size` rounded up to whole huge pages. Where the kernel gives huge pages only on request
    /// (transparent_hugepage "madvise"), madvise asks; elsewhere it is a harmless hint.
    static Block new_block(std::size_t size) {
        size = (size + kHugePage - 1) & ~(kHugePage - 1);
        auto* p = static_cast<std::byte*>(::operator new[](size, std::align_val_t(kHugePage)));
#ifdef __linux__
        madvise(p, size, MADV_HUGEPAGE);
#endif
        return {std::unique_ptr<std::byte[], FreeBlock>(p), size};
    }

    std::byte* allocate_bytes(std::size_t bytes) {
        bytes = (bytes + kAlign - 1) & ~(kAlign - 1);
        if (current_ < blocks_.size() && offset_ + bytes <= blocks_[current_].bytes) [[likely]] {
            std::byte* out = blocks_[current_].data.get() + offset_;
            offset_ += bytes;
            return out;
        }
        return allocate_in_next_block(bytes);
    }

    [[gnu::noinline]] std::byte* allocate_in_next_block(std::size_t bytes) {
        // Blocks after the current one hold nothing live; skip those too small for the request.
        do {
            ++current_;
        } while (current_ < blocks_.size() && bytes > blocks_[current_].bytes);
        if (current_ >= blocks_.size()) {
            current_ = blocks_.size();
            const std::size_t size = std::max(kMinBlockBytes, 4 * bytes);  // room for what follows
            blocks_.push_back(new_block(size));
        }
        offset_ = bytes;
        return blocks_[current_].data.get();
    }

    std::vector<Block> blocks_;
    std::size_t current_ = 0, offset_ = 0;
};

}  // namespace trident::kd
