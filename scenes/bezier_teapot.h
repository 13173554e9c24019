#pragma once
// The Utah teapot tessellated from Newell's bicubic Bezier patches, y up (the data is z up).
#include <cstddef>
#include <cstdint>

#include "core/mesh.h"

namespace trident {

/// At 1 segment the handle's and spout's two half-tubes collapse onto each other (their corners
/// all lie in the symmetry plane), so 2 is the least that gives a proper surface.
inline constexpr std::uint32_t kMinTeapotSegments = 2;
/// Largest `segments` for which patch evaluation stays exact enough to weld seams (see the .cpp).
inline constexpr std::uint32_t kMaxTeapotSegments = 24;

/// Each of the 32 patches as a segments x segments grid of quads, two triangles each. Points on
/// shared patch boundaries are evaluated bit-identically and welded, so seams share edges; the
/// zero-area triangles at the collapsed patch edges (lid knob and bottom poles) are dropped.
/// The result is not closed: the lid floats in the body's opening, and the handle and spout ends
/// are open. Throws std::invalid_argument unless kMinTeapotSegments <= segments <= kMaxTeapotSegments.
Mesh make_bezier_teapot(std::uint32_t segments);

/// Triangle count of make_bezier_teapot(segments) without tessellating: 64 segments^2 minus
/// `segments` for each patch edge collapsed to a point (8 of them, so 6320 at 10 segments).
std::size_t bezier_teapot_triangle_count(std::uint32_t segments);

}  // namespace trident
