#pragma once
// The hit buffer of ../shared/BENCHMARK.md: magic "RTHITS1\0", uint32 width and height, then per
// pixel (row-major, top row first) int32 triangle (-1 for a miss) and float32 t (+inf for a miss),
// all little-endian.
#include <cstdint>
#include <filesystem>
#include <vector>

#include "core/ray.h"

namespace trident {

struct HitBuffer {
    std::uint32_t width = 0, height = 0;
    std::vector<std::int32_t> triangle;
    std::vector<float> t;
};

HitBuffer make_hit_buffer(std::uint32_t width, std::uint32_t height, const std::vector<Hit>& hits);

/// Throws std::runtime_error naming the file on I/O errors, a wrong magic or a truncated file.
void write_hit_buffer(const std::filesystem::path& path, const HitBuffer& buffer);
HitBuffer read_hit_buffer(const std::filesystem::path& path);

/// The error figures of BENCHMARK.md between two traces of the same rays.
struct HitBufferComparison {
    std::uint64_t rays = 0;
    std::uint64_t hit_miss_differ = 0;    // one hits, the other misses
    std::uint64_t triangle_differ = 0;    // both hit, different triangles
    double max_relative_t_difference = 0.0;  // among rays that both hit
    double hit_miss_share() const { return rays ? double(hit_miss_differ) / double(rays) : 0.0; }
    double triangle_share() const { return rays ? double(triangle_differ) / double(rays) : 0.0; }
};

/// Throws std::invalid_argument when the sizes differ.
HitBufferComparison compare_hit_buffers(const HitBuffer& test, const HitBuffer& reference);

}  // namespace trident
