#pragma once
// Whether a packet's rays travel together: the cone test the wide BVH's packet switch
// (wide_packet_switch in wide_packet.h) reads, over a packet's lanes or over the rays a caller
// still holds one by one, and the rule it sets for incoherent packets over a large tree (every
// lane alone from the root), which a caller holding the rays can apply before building the packet.
// Only a choice of walk depends on any of it, never a hit.
#include <cstddef>
#include <span>
#include <xsimd/xsimd.hpp>

#include "core/ray.h"
#include "core/vec3.h"
#include "simd/packet.h"

namespace trident {

/// The wide BVH's packet switch reads these; wide_packet_switch says how, and what they measured.
inline constexpr int kWideSingleRayLanes = 1;
inline constexpr float kCoherentCosine = 0.9f;
inline constexpr float kIncoherentMinLaneUse = 0.5f;
inline constexpr std::size_t kIncoherentLaneUseLevels = 2;
inline constexpr std::size_t kIncoherentAloneMinBlocks = 8192;

namespace bvh {

/// Whether `dir` lies outside the cone around `axis` whose half-angle has cosine c, given
/// bound_scale = c^2 |axis|^2: cos(dir, axis) >= c squared to need no root, dot >= 0 and
/// dot^2 >= c^2 |dir|^2 |axis|^2. T is float or a batch of lanes, with the same operations.
template <class T>
auto outside_cone(const Vec3T<T>& dir, const Vec3T<T>& axis, float bound_scale) {
    const T along = dot(dir, axis);
    return (along < T(0.0f)) | (along * along < T(bound_scale) * dot(dir, dir));
}

/// Whether every live lane's direction lies within the cone around lane 0's direction whose
/// half-angle has cosine `cos_half_angle` (lane 0 holds a finite direction even when inactive).
/// The directions need not be unit length. Lane 0 rather than the lanes' mean as the axis: three
/// horizontal sums per packet cost Teapot's primary packets several per cent (perf), where the
/// walk itself is short.
template <class Arch>
bool directions_within_cone(const RayPacket<Arch>& rays, float cos_half_angle) {
    using Float = typename RayPacket<Arch>::Float;
    const Vec3T<float> axis(rays.dir.x.get(0), rays.dir.y.get(0), rays.dir.z.get(0));
    const float axis_length2 = dot(axis, axis);
    if (!(axis_length2 > 0.0f)) return false;
    const Vec3T<Float> lane_axis(Float(axis.x), Float(axis.y), Float(axis.z));
    const float bound_scale = cos_half_angle * cos_half_angle * axis_length2;
    return !xsimd::any(rays.active & outside_cone(rays.dir, lane_axis, bound_scale));
}

/// The same over rays held one by one: the directions direction_of(0), ..., direction_of(count - 1)
/// (a packet's rays before it is built, read where they lie); the first is the axis.
template <class DirectionOf>
bool directions_within_cone(std::size_t count, DirectionOf&& direction_of, float cos_half_angle) {
    if (count == 0) return true;
    const Vec3f axis = direction_of(0);
    const float axis_length2 = dot(axis, axis);
    if (!(axis_length2 > 0.0f)) return false;
    const float bound_scale = cos_half_angle * cos_half_angle * axis_length2;
    for (std::size_t k = 1; k < count; ++k)
        if (outside_cone(direction_of(k), axis, bound_scale)) return false;
    return true;
}

/// Whether an incoherent packet walks every lane alone from the root of a tree of `tree_blocks`
/// blocks (else it goes ray by ray only where its lanes part).
inline bool incoherent_lanes_alone_from_root(std::size_t tree_blocks) {
    return tree_blocks >= kIncoherentAloneMinBlocks;
}

/// Whether the packet of the rays rays[index[0]], rays[index[1]], ... (at most one packet's
/// width) walks every lane alone from the root of a tree of `tree_blocks` blocks under the
/// structure's own switch: the packet would be built only to be taken apart again.
inline bool lanes_walk_alone(std::span<const Ray> rays, std::span<const std::size_t> index, std::size_t tree_blocks) {
    return incoherent_lanes_alone_from_root(tree_blocks) &&
           !directions_within_cone(index.size(), [&](std::size_t k) { return rays[index[k]].dir; }, kCoherentCosine);
}

}  // namespace bvh

}  // namespace trident
