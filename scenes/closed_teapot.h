#pragma once
// A teapot-shaped closed mesh for watertightness stress tests (rays from inside must all hit).
// Newell's patch teapot is open (lid gap, spout and handle ends), so this one is built from
// closed solids instead: body, lid and knob as one lathe, a torus handle and a tapered spout.
// The solids interpenetrate, as a modeller's would; each is watertight and wound outwards, so
// every edge of the mesh is shared by exactly two consistently wound triangles.
#include <cstdint>

#include "core/mesh.h"

namespace trident {

/// `segments` around the body (at least 8); the handle and spout scale with it.
Mesh make_closed_teapot_like_mesh(std::uint32_t segments = 48);

}  // namespace trident
