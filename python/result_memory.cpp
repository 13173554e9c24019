#include "result_memory.h"

#include <sys/mman.h>

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <new>
#include <unordered_map>
#include <vector>

namespace trident::python {

namespace {

constexpr std::size_t kPageBytes = std::size_t(2) << 20;
// Two, so that `hits = scene.intersect(rays)` in a loop, where the last result is freed only once
// the next one is made, still finds memory to reuse.
constexpr std::size_t kKeptBuffers = 2;

class ResultPool {
public:
    float* take(std::size_t bytes) {
        const std::size_t rounded = (bytes + kPageBytes - 1) / kPageBytes * kPageBytes;
        std::lock_guard lock(mutex_);
        float* data = nullptr;
        for (auto it = kept_.begin(); it != kept_.end(); ++it)
            if (it->bytes == rounded) {
                data = it->data;
                kept_.erase(it);
                break;
            }
        if (!data) {
            data = static_cast<float*>(std::aligned_alloc(kPageBytes, rounded));
            if (!data) throw std::bad_alloc();
            madvise(data, rounded, MADV_HUGEPAGE);  // a hint: without it, 4 KiB pages
        }
        in_use_[data] = rounded;
        return data;
    }

    void give_back(float* data) {
        std::lock_guard lock(mutex_);
        const auto found = in_use_.find(data);
        kept_.push_back({found->second, data});
        in_use_.erase(found);
        if (kept_.size() > kKeptBuffers) {
            std::free(kept_.front().data);
            kept_.erase(kept_.begin());
        }
    }

private:
    struct Buffer {
        std::size_t bytes;
        float* data;
    };
    std::mutex mutex_;
    std::vector<Buffer> kept_;  // oldest first
    std::unordered_map<float*, std::size_t> in_use_;
};

// Never destroyed: numpy may free the last arrays after static destructors have run.
ResultPool& pool() {
    static auto* const instance = new ResultPool;
    return *instance;
}

}  // namespace

pybind11::array_t<float> pooled_float_array(std::size_t rows, std::size_t columns) {
    float* data = pool().take(std::max<std::size_t>(rows * columns, 1) * sizeof(float));
    pybind11::capsule owner(data, [](void* p) { pool().give_back(static_cast<float*>(p)); });
    return pybind11::array_t<float>({pybind11::ssize_t(rows), pybind11::ssize_t(columns)}, data, owner);
}

}  // namespace trident::python
