#pragma once
// Memory for large batches' results, kept between calls. A batch of full-HD closest hits is 33 MB:
// in fresh memory the kernel clears every page as the tracing threads first touch it, and in
// reused memory a normal store reads each line first, from DRAM at that size. Reused and written
// with streaming stores (render/ray_arrays.h: RayImage::stream_results), it costs neither: Teapot's
// 16-lane batch at two threads took 0.89x the time of fresh numpy memory with normal stores, where
// either change alone gained nothing (bench/experiments/python_module.md).
#include <pybind11/numpy.h>

#include <cstddef>

namespace trident::python {

/// Results of at least this many bytes go to pooled memory and are written with streaming stores;
/// smaller ones stay in numpy's memory, where they are likely still cached when read.
inline constexpr std::size_t kPooledResultBytes = std::size_t(4) << 20;

/// A C-contiguous float32 array of `rows` x `columns` in memory aligned to 2 MiB pages (huge pages
/// where the kernel allows): a buffer freed by an earlier result of the same rounded size when one
/// is kept, new memory otherwise. When the array and every view of it are gone, its memory is kept
/// for the next such request: at most two buffers are kept, the oldest freed first.
pybind11::array_t<float> pooled_float_array(std::size_t rows, std::size_t columns);

}  // namespace trident::python
