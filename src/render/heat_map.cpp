#include "render/heat_map.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

#include "render/render_kernels.h"
#include "render/secondary_rays.h"
#include "render/trace.h"

namespace trident {
namespace {

// A perceptually ordered ramp (dark blue -> teal -> yellow -> white-hot), sampled linearly.
constexpr std::array<Vec3f, 5> kRamp{Vec3f{0.02f, 0.02f, 0.10f}, Vec3f{0.10f, 0.25f, 0.60f}, Vec3f{0.10f, 0.65f, 0.55f},
                                     Vec3f{0.95f, 0.85f, 0.20f}, Vec3f{1.0f, 1.0f, 1.0f}};

Rgb8 ramp(float s01) {
    const float s = std::clamp(s01, 0.0f, 1.0f) * float(kRamp.size() - 1);
    const auto k = std::min(std::size_t(s), kRamp.size() - 2);
    const float f = s - float(k);
    const Vec3f c = kRamp[k] * (1.0f - f) + kRamp[k + 1] * f;
    return {std::uint8_t(c.x * 255.0f), std::uint8_t(c.y * 255.0f), std::uint8_t(c.z * 255.0f)};
}

// 3x5 digit glyphs, one row of 3 bits per entry, top row first, most significant bit on the left.
constexpr std::array<std::array<std::uint8_t, 5>, 10> kDigitGlyphs{{
    {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
    {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 2, 2, 2}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7},
}};

void fill(Image& image, std::uint32_t x0, std::uint32_t y0, std::uint32_t w, std::uint32_t h, Rgb8 colour) {
    for (std::uint32_t y = y0; y < std::min(y0 + h, image.height); ++y)
        for (std::uint32_t x = x0; x < std::min(x0 + w, image.width); ++x) image.at(x, y) = colour;
}

bool same(Rgb8 a, Rgb8 b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

constexpr Rgb8 kLegendInk{255, 255, 255};
constexpr Rgb8 kLegendPaper{0, 0, 0};

/// The bar, with the minimum at its left and the maximum at its right, in a black strip at the
/// bottom of the image.
void draw_legend(Image& image, std::uint64_t lowest, std::uint64_t highest) {
    const HeatLegendLayout layout = heat_legend_layout(image.width, image.height, highest);
    const std::uint32_t scale = layout.scale, pad = 2 * scale, glyph_h = 5 * scale, y = layout.digits_y;
    fill(image, 0, layout.strip_top, image.width, image.height - layout.strip_top, kLegendPaper);
    const std::uint32_t left = layout.min_x + draw_digits(image, layout.min_x, y, lowest, scale, kLegendInk) + pad;
    const std::uint32_t right = layout.max_x;
    draw_digits(image, right, y, highest, scale, kLegendInk);
    if (right > left + pad) {
        const std::uint32_t bar_w = right - pad - left;
        for (std::uint32_t i = 0; i < bar_w; ++i) fill(image, left + i, y, 1, glyph_h, ramp(float(i) / float(std::max(bar_w - 1, 1u))));
    }
}

}  // namespace

HeatLegendLayout heat_legend_layout(std::uint32_t image_width, std::uint32_t image_height, std::uint64_t highest) {
    const std::uint32_t scale = std::max(2u, image_height / 160);
    const std::uint32_t pad = 2 * scale, strip_h = 5 * scale + 2 * pad;
    const std::uint32_t max_w = std::uint32_t(std::to_string(highest).size()) * 4 * scale;
    const std::uint32_t max_x = image_width > max_w + pad ? image_width - max_w - pad : image_width;
    return {scale, image_height - strip_h, image_height - strip_h + pad, pad, max_x};
}

std::vector<TraversalCounters> count_primary_rays(const AnyAccel& accel, const Camera& camera, SimdWidth width,
                                                  TriangleTest test) {
    if (width == SimdWidth::scalar) return count_primary(accel, camera, test);
    std::vector<TraversalCounters> counts(std::size_t(camera.width()) * camera.height());
    accel.visit([&](const auto& structure) {
        using Structure = std::decay_t<decltype(structure)>;
        dispatch_width(width, [&]<SimdWidth W>() {
            if constexpr (W != SimdWidth::scalar)
                for_each_image_tile(camera, [&](const ImageTile& tile) {
                    RenderKernels<Structure, W>::count_primary_tile(structure, camera, tile, counts, test);
                });
        });
    });
    return counts;
}

std::uint32_t draw_digits(Image& image, std::uint32_t x, std::uint32_t y, std::uint64_t value, std::uint32_t scale,
                          Rgb8 colour) {
    const std::string text = std::to_string(value);
    std::uint32_t cx = x;
    for (char c : text) {
        const auto& glyph = kDigitGlyphs[std::size_t(c - '0')];
        for (std::uint32_t row = 0; row < 5; ++row)
            for (std::uint32_t col = 0; col < 3; ++col)
                if ((glyph[row] >> (2 - col)) & 1u) fill(image, cx + col * scale, y + row * scale, scale, scale, colour);
        cx += 4 * scale;
    }
    return cx - x - scale;
}

int read_digit(const Image& image, std::uint32_t x, std::uint32_t y, std::uint32_t scale, Rgb8 colour) {
    std::array<std::uint8_t, 5> rows{};
    for (std::uint32_t row = 0; row < 5; ++row)
        for (std::uint32_t col = 0; col < 3; ++col) {
            const std::uint32_t px = x + col * scale, py = y + row * scale;
            if (px < image.width && py < image.height && same(image.at(px, py), colour))
                rows[row] = std::uint8_t(rows[row] | (1u << (2 - col)));
        }
    for (std::size_t d = 0; d < kDigitGlyphs.size(); ++d)
        if (kDigitGlyphs[d] == rows) return int(d);
    return -1;
}

Image shade_heat(const Camera& camera, const std::vector<TraversalCounters>& counts, HeatMeasure measure) {
    Image image(camera.width(), camera.height());
    auto figure = [&](const TraversalCounters& c) {
        return measure == HeatMeasure::nodes ? c.nodes_visited : c.triangles_tested;
    };
    std::uint64_t lowest = ~std::uint64_t(0), highest = 0;
    for (const TraversalCounters& c : counts) {
        lowest = std::min(lowest, figure(c));
        highest = std::max(highest, figure(c));
    }
    if (counts.empty()) lowest = 0;
    const float range = highest > lowest ? float(highest - lowest) : 1.0f;
    for (std::size_t i = 0; i < counts.size(); ++i) image.pixels[i] = ramp(float(figure(counts[i]) - lowest) / range);
    if (image.width >= kLegendMinWidth && image.height >= kLegendMinHeight) draw_legend(image, lowest, highest);
    return image;
}

}  // namespace trident
