#pragma once
// OBJ loading through tinyobjloader. Polygons are triangulated (a quad is split along its shorter
// diagonal, larger polygons as a fan: tinyobjloader's rule) and triangles keep file order: triangle
// i is the i-th face after triangulation, which the hit buffer relies on.
#include <filesystem>

#include "core/mesh.h"

namespace trident {

/// Throws SceneError (one line naming the file and, where the parser gives one, the line) on a
/// missing or unreadable file, malformed lines, faces whose indices are out of range, non-finite
/// coordinates, or a file without triangles.
Mesh load_obj(const std::filesystem::path& path);

/// Checks what every mesh must satisfy before a structure is built over it (finite coordinates,
/// indices in range, at least one triangle); `what` names the mesh in the message.
void validate_mesh(const Mesh& mesh, const std::string& what);

}  // namespace trident
