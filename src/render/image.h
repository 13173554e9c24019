#pragma once
// 8-bit RGB images and PNG files (stb_image_write, linked from Debian's libstb).
#include <cstdint>
#include <filesystem>
#include <vector>

namespace trident {

struct Rgb8 {
    std::uint8_t r, g, b;
};

struct Image {
    std::uint32_t width = 0, height = 0;
    std::vector<Rgb8> pixels;  // row-major, top row first

    Image() = default;
    Image(std::uint32_t w, std::uint32_t h) : width(w), height(h), pixels(std::size_t(w) * h, Rgb8{0, 0, 0}) {}
    Rgb8& at(std::uint32_t x, std::uint32_t y) { return pixels[std::size_t(y) * width + x]; }
    const Rgb8& at(std::uint32_t x, std::uint32_t y) const { return pixels[std::size_t(y) * width + x]; }
};

/// Throws std::runtime_error naming the file when it cannot be written / read.
void write_png(const std::filesystem::path& path, const Image& image);
Image read_png(const std::filesystem::path& path);

}  // namespace trident
