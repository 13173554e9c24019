#include "scenes/closed_teapot.h"

#include <algorithm>
#include <numbers>
#include <stdexcept>

#include "scenes/mesh_builder.h"

namespace trident {

Mesh make_closed_teapot_like_mesh(std::uint32_t segments) {
    if (segments < 8) throw std::invalid_argument("closed teapot: needs at least 8 segments");
    MeshBuilder b;
    // Counter-clockwise in (radius, height): bottom pole, up the body, over the lid, knob pole.
    b.add(Lathe{{{0.0f, 0.0f},
                 {1.3f, 0.0f},
                 {1.5f, 0.15f},
                 {1.85f, 0.45f},
                 {2.0f, 0.9f},
                 {2.0f, 1.35f},
                 {1.75f, 1.9f},
                 {1.5f, 2.4f},
                 {1.3f, 2.55f},
                 {0.8f, 2.65f},
                 {0.2f, 2.75f},
                 {0.2f, 2.85f},
                 {0.45f, 3.0f},
                 {0.3f, 3.15f},
                 {0.0f, 3.18f}},
                segments});
    const std::uint32_t tube = std::max(6u, segments / 4);
    b.add(torus(0.75f, 0.15f, 0.0f, segments, tube), translation({-2.05f, 1.55f, 0.0f}) * scaling({1.0f, 1.25f, 1.0f}) *
                                                         rotation_x(0.5f * std::numbers::pi_v<float>));
    b.add(Lathe{{{0.4f, 0.0f}, {0.3f, 0.9f}, {0.16f, 1.9f}}, std::max(8u, segments / 2)},
          translation({1.6f, 0.75f, 0.0f}) * y_along({1.0f, 1.15f, 0.0f}));
    return b.build();
}

}  // namespace trident
