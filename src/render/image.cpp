#include "render/image.h"

#include <fmt/format.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include <stdexcept>

namespace trident {

static_assert(sizeof(Rgb8) == 3, "pixels are written as packed RGB");

void write_png(const std::filesystem::path& path, const Image& image) {
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
