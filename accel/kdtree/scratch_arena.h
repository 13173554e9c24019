#pragma once
// A last-in-first-out scratch allocator. The kd-tree builder takes a mark before splitting a node
// and releases back to it once both children are built, so the millions of small event lists near
// the leaves cost no heap traffic. Blocks are kept for reuse until the arena dies. One arena per
// thread: a task that runs on a thread while another waits there is nested inside it and
// releases its memory before returning, so the last-in-first-out order holds.
#include <algorithm>
#include <cstddef>
#include <memory>
#include <span>
#include <type_traits>
#include <vector>

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

    struct Block {
        std::unique_ptr<std::byte[]> data;
        std::size_t bytes;
    };

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
            blocks_.push_back({std::make_unique_for_overwrite<std::byte[]>(size), size});
        }
        offset_ = bytes;
        return blocks_[current_].data.get();
    }

    std::vector<Block> blocks_;
    std::size_t current_ = 0, offset_ = 0;
};

}  // namespace trident::kd
