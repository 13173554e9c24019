#pragma once
// A caller's hint of how alike a list's rays are, as Embree's coherent and incoherent context
// flags: rays of a camera's tile are coherent (neighbours walk the same nodes), diffuse bounces
// are not. A structure may walk incoherent rays differently; the hits are the same either way.
#include <cstdint>

#include "core/intersect_triangle.h"
#include "core/ray.h"
#include "core/slab_test.h"

namespace trident {

enum class RayCoherence : std::uint8_t { coherent, incoherent };

/// The closest hit of `ray` by the structure's single-ray walk, the hint passed on to a structure
/// that takes it (the wide BVH) and dropped for the others.
template <TriangleTest Test, SlabTest Slabs, class Structure, class Counters>
Hit intersect_hinted(const Structure& structure, const Ray& ray, Counters& counters, RayCoherence coherence) {
    if constexpr (requires { structure.template intersect<Test, Slabs>(ray, counters, coherence); })
        return structure.template intersect<Test, Slabs>(ray, counters, coherence);
    else
        return structure.template intersect<Test, Slabs>(ray, counters);
}

}  // namespace trident
