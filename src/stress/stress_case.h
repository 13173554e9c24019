#pragma once
// One stress case: a mesh, the rays shot at it, and what each ray must or must not do beyond
// agreeing with the double-precision reference (core/reference.h).
#include <cstdint>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/ray.h"

namespace trident {

struct StressCase {
    std::string name;
    Mesh mesh;
    std::vector<Ray> rays;
    /// Per ray: it starts inside a closed mesh, so every structure must report a hit; a miss is a leak.
    std::vector<std::uint8_t> must_hit;
    /// Per ray: the triangle it starts on (offset off it), which it must never hit; kNoTriangle if none.
    std::vector<TriangleId> start_triangle;

    void add_ray(const Ray& ray, bool inside_closed_mesh, TriangleId start = kNoTriangle) {
        rays.push_back(ray);
        must_hit.push_back(inside_closed_mesh ? 1 : 0);
        start_triangle.push_back(start);
    }
};

}  // namespace trident
