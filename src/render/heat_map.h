#pragma once
// Heat maps: the traversal cost of each primary ray (nodes visited or triangles tested) on a
// colour ramp, with a legend drawn into the image (ramp bar and its minimum and maximum).
#include <cstdint>
#include <vector>

#include "accel/any_accel.h"
#include "camera/camera.h"
#include "core/intersect_triangle.h"
#include "render/image.h"
#include "render/render_plan.h"
#include "simd/width.h"

namespace trident {

/// Counters per pixel for the primary rays. Scalar: each ray's own count. Packets (2x2 / 4x2 /
/// 4x4 blocks as trace_primary's): the structures count per packet, so every pixel of a block
/// gets its packet's count (what the packet cost, shared by its lanes). Throws as trace_primary.
std::vector<TraversalCounters> count_primary_rays(const AnyAccel& accel, const Camera& camera, SimdWidth width,
                                                  TriangleTest test = TriangleTest::watertight);

/// The measure per pixel on the ramp, scaled from the image's minimum to its maximum, with the
/// legend at the bottom when the image is at least kLegendMinWidth x kLegendMinHeight.
Image shade_heat(const Camera& camera, const std::vector<TraversalCounters>& counts, HeatMeasure measure);

inline constexpr std::uint32_t kLegendMinWidth = 64, kLegendMinHeight = 48;

/// Where the legend sits: a black strip at the bottom; digits `scale` pixels per font pixel, their
/// top row at digits_y; the minimum starts at min_x, the maximum at max_x; the bar between them.
struct HeatLegendLayout {
    std::uint32_t scale, strip_top, digits_y, min_x, max_x;
};
HeatLegendLayout heat_legend_layout(std::uint32_t image_width, std::uint32_t image_height, std::uint64_t highest);

/// Draws decimal digits (0-9 only) with a 3x5 pixel font scaled by `scale`, top-left at (x, y);
/// clipped to the image. Returns the width drawn.
std::uint32_t draw_digits(Image& image, std::uint32_t x, std::uint32_t y, std::uint64_t value, std::uint32_t scale,
                          Rgb8 colour);

/// The value a pixel of the legend's digits spells, read back (for tests): the 3x5 glyph under
/// (x, y) at `scale`, or -1 if the pixels there are no digit.
int read_digit(const Image& image, std::uint32_t x, std::uint32_t y, std::uint32_t scale, Rgb8 colour);

}  // namespace trident
