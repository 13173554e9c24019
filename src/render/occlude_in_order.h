#pragma once
// Shadow rays of a list answered in order, ray after ray, so that a structure can carry what one
// ray learnt to the next: the wide BVH tries the block of triangles that stopped the ray before
// first (LastOccluder in accel/packet_kernels.h).
#include <cstddef>
#include <cstdint>
#include <span>

#include "accel/accel_stats.h"
#include "accel/packet_kernels.h"
#include "core/intersect_triangle.h"
#include "core/ray.h"
#include "core/slab_test.h"
#include "render/stream_packets.h"

namespace trident {

/// Whether each ray of a list is blocked, in order, into `out` (untraceable rays: not blocked).
/// With `last_occluder`, a structure that tests the last occluder first (LastOccluder: the wide
/// BVH) carries it along the list; the answers are occluded()'s either way.
template <TriangleTest Test, SlabTest Slabs, class Structure>
void occlude_in_order(const Structure& structure, std::span<const Ray> rays, std::span<std::uint8_t> out,
                      bool last_occluder) {
    constexpr bool kTriesLastOccluder = requires(NoCounters counters, LastOccluder last) {
        structure.template occluded<Test, Slabs>(rays[0], counters, last);
    };
    if constexpr (kTriesLastOccluder) {
        if (last_occluder) {
            LastOccluder last;
            for (std::size_t i = 0; i < rays.size(); ++i) {
                NoCounters counters;
                out[i] = is_traced(rays[i]) && structure.template occluded<Test, Slabs>(rays[i], counters, last);
            }
            return;
        }
    }
    for (std::size_t i = 0; i < rays.size(); ++i) {
        NoCounters counters;
        out[i] = is_traced(rays[i]) && structure.template occluded<Test, Slabs>(rays[i], counters);
    }
}

}  // namespace trident
