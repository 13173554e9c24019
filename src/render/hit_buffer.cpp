#include "render/hit_buffer.h"

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace trident {
namespace {

constexpr char kMagic[8] = {'R', 'T', 'H', 'I', 'T', 'S', '1', '\0'};

void put_u32(std::vector<char>& out, std::uint32_t value) {
    for (int i = 0; i < 4; ++i) out.push_back(char((value >> (8 * i)) & 0xFFu));
}
std::uint32_t get_u32(const char* p) {
    std::uint32_t value = 0;
    for (int i = 0; i < 4; ++i) value |= std::uint32_t(std::uint8_t(p[i])) << (8 * i);
    return value;
}

}  // namespace

HitBuffer make_hit_buffer(std::uint32_t width, std::uint32_t height, const std::vector<Hit>& hits) {
    HitBuffer buffer{width, height, {}, {}};
    buffer.triangle.resize(hits.size());
    buffer.t.resize(hits.size());
    for (std::size_t i = 0; i < hits.size(); ++i) {
        buffer.triangle[i] = hits[i].is_hit() ? std::int32_t(hits[i].triangle) : -1;
        buffer.t[i] = hits[i].is_hit() ? hits[i].t : kInfinity;
    }
    return buffer;
}

void write_hit_buffer(const std::filesystem::path& path, const HitBuffer& buffer) {
    std::vector<char> bytes(kMagic, kMagic + 8);
    bytes.reserve(16 + buffer.triangle.size() * 8);
    put_u32(bytes, buffer.width);
    put_u32(bytes, buffer.height);
    for (std::size_t i = 0; i < buffer.triangle.size(); ++i) {
        put_u32(bytes, std::bit_cast<std::uint32_t>(buffer.triangle[i]));
        put_u32(bytes, std::bit_cast<std::uint32_t>(buffer.t[i]));
    }
    std::ofstream out(path, std::ios::binary);
    if (!out.write(bytes.data(), std::streamsize(bytes.size())))
        throw std::runtime_error(fmt::format("{}: cannot write the hit buffer", path.string()));
}

HitBuffer read_hit_buffer(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(fmt::format("{}: cannot open the hit buffer", path.string()));
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.size() < 16 || std::memcmp(bytes.data(), kMagic, 8) != 0)
        throw std::runtime_error(fmt::format("{}: not a hit buffer (bad magic)", path.string()));
    HitBuffer buffer;
    buffer.width = get_u32(bytes.data() + 8);
    buffer.height = get_u32(bytes.data() + 12);
    const std::size_t pixels = std::size_t(buffer.width) * buffer.height;
    if (bytes.size() != 16 + pixels * 8)
        throw std::runtime_error(fmt::format("{}: truncated hit buffer ({} bytes for {}x{})", path.string(),
                                             bytes.size(), buffer.width, buffer.height));
    buffer.triangle.resize(pixels);
    buffer.t.resize(pixels);
    for (std::size_t i = 0; i < pixels; ++i) {
        buffer.triangle[i] = std::bit_cast<std::int32_t>(get_u32(bytes.data() + 16 + 8 * i));
        buffer.t[i] = std::bit_cast<float>(get_u32(bytes.data() + 20 + 8 * i));
    }
    return buffer;
}

HitBufferComparison compare_hit_buffers(const HitBuffer& test, const HitBuffer& reference) {
    if (test.width != reference.width || test.height != reference.height)
        throw std::invalid_argument(fmt::format("hit buffers differ in size: {}x{} against {}x{}", test.width,
                                                test.height, reference.width, reference.height));
    HitBufferComparison result;
    result.rays = test.triangle.size();
    for (std::size_t i = 0; i < test.triangle.size(); ++i) {
        const bool test_hit = test.triangle[i] >= 0, reference_hit = reference.triangle[i] >= 0;
        if (test_hit != reference_hit) {
            ++result.hit_miss_differ;
        } else if (test_hit) {
            if (test.triangle[i] != reference.triangle[i]) ++result.triangle_differ;
            const double r = double(reference.t[i]);
            const double relative = std::abs(double(test.t[i]) - r) / std::max(std::abs(r), 1e-30);
            result.max_relative_t_difference = std::max(result.max_relative_t_difference, relative);
        }
    }
    return result;
}

}  // namespace trident
