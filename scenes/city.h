#pragma once
// "city": about a million triangles of city blocks seen from street level down an avenue. Every
// facade carries its windows and floor ledges as separate boxes; streets hold parked cars, trees
// and lamp posts; roofs hold water tanks and stair huts.
#include <cstddef>

#include "core/scene.h"
#include "scenes/mesh_builder.h"

namespace trident {

/// The city as placed parts (cheap: no triangles are generated).
MeshBuilder city_parts();
std::size_t city_triangle_count();
Scene make_city_scene();

}  // namespace trident
