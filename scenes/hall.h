#pragma once
// "hall": a columned hall seen from inside at eye height, the complex interior of the set. Two
// arcades of fluted columns divide nave and aisles under a coffered ceiling; tables, chairs and
// chandeliers fill the nave. Nearly every primary ray stops on something close.
#include <cstddef>

#include "core/scene.h"
#include "scenes/mesh_builder.h"

namespace trident {

/// The hall as placed parts (cheap: no triangles are generated).
MeshBuilder hall_parts();
std::size_t hall_triangle_count();
Scene make_hall_scene();

}  // namespace trident
