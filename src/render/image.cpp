#include "render/image.h"

#include <fmt/format.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include <stdexcept>

namespace trident {

static_assert(sizeof(Rgb8) == 3, "pixels are written as packed RGB");

void write_png(const std::filesystem::path& path, const Image& image) {
    // stb's defaults (level 8, the best of five filters tried on every row) took longer to write
    // the teapot's 1920x1080 render than to trace and shade it. One filter, each row against the
    // one above, at level 4 wrote Sponza, a heat map and the teapot 1.85-2.0x as fast, in files -2%
    // to +6% the size (bench/experiments/png_output.md).
    stbi_write_png_compression_level = 4;
    stbi_write_force_png_filter = 2;  // "up"
    const int stride = int(image.width) * 3;
    if (!stbi_write_png(path.string().c_str(), int(image.width), int(image.height), 3, image.pixels.data(), stride))
        throw std::runtime_error(fmt::format("{}: cannot write the PNG file", path.string()));
}

Image read_png(const std::filesystem::path& path) {
    int w = 0, h = 0, channels = 0;
    stbi_uc* data = stbi_load(path.string().c_str(), &w, &h, &channels, 3);
    if (!data) throw std::runtime_error(fmt::format("{}: cannot read the PNG file", path.string()));
    Image image{std::uint32_t(w), std::uint32_t(h)};
    for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = {data[3 * i], data[3 * i + 1], data[3 * i + 2]};
    stbi_image_free(data);
    return image;
}

}  // namespace trident
