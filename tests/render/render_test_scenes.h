#pragma once
// Small scenes with known shadows for the render tests.
#include <vector>

#include "accel/any_accel.h"
#include "core/scene.h"
#include "simd/width.h"

namespace trident::testing {

/// Two triangles spanning [x0, x1] x [z0, z1] at height y, facing +y.
inline void add_floor_quad(Mesh& mesh, float x0, float x1, float z0, float z1, float y) {
    const auto a = mesh.add_vertex({x0, y, z0}), b = mesh.add_vertex({x1, y, z0});
    const auto c = mesh.add_vertex({x1, y, z1}), d = mesh.add_vertex({x0, y, z1});
    mesh.add_triangle(a, c, b);
    mesh.add_triangle(a, d, c);
}

/// Every traversal the renderer may run here: single rays and each runnable packet width.
inline std::vector<SimdWidth> runnable_widths() {
    std::vector<SimdWidth> widths;
    for (SimdWidth width : kSimdWidths)
        if (is_runnable(width)) widths.push_back(width);
    return widths;
}

}  // namespace trident::testing
