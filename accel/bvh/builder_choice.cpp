#include "accel/bvh/builder_choice.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace trident::bvh {

namespace {

constexpr std::size_t kChunk = std::size_t(1) << 14;

struct AreaSums {
    double all = 0.0, large = 0.0;
};

}  // namespace

double large_triangle_share(const Mesh& mesh) {
    const std::size_t count = mesh.triangle_count();
    const double scene_area = surface_area_in_double(mesh.bounds());
    if (count == 0 || !(scene_area > 0.0)) return 0.0;
    const double large_from = kLargeTriangleArea * scene_area;
    std::vector<AreaSums> chunks((count + kChunk - 1) / kChunk);
    tbb::parallel_for(std::size_t(0), chunks.size(), [&](std::size_t c) {
        AreaSums sums;
        for (std::size_t i = c * kChunk, end = std::min(count, i + kChunk); i < end; ++i) {
            const double area = surface_area_in_double(triangle_of(mesh, i).bounds());
            sums.all += area;
            if (area > large_from) sums.large += area;
        }
        chunks[c] = sums;
    });
    AreaSums total;
    for (const AreaSums& sums : chunks) {
        total.all += sums.all;
        total.large += sums.large;
    }
    return total.all > 0.0 ? total.large / total.all : 0.0;
}

}  // namespace trident::bvh
