#pragma once
// Closed solids the procedural scenes are assembled from. Each shape knows its vertex and
// triangle counts without being generated (so scene sizes are known up front) and writes itself
// through a PartWriter, counter-clockwise seen from outside, with no zero-area triangles as long
// as its dimensions are positive.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "scenes/part_writer.h"

namespace trident {

/// Axis-aligned box from lo to hi: 8 vertices, 12 triangles.
struct Box {
    Vec3f lo, hi;

    std::uint32_t vertex_count() const { return 8; }
    std::size_t triangle_count() const { return 12; }
    void emit(PartWriter& out) const;
};

/// A point of a lathe profile: distance from the y axis and height.
struct ProfilePoint {
    float radius, height;
};

/// Surface of revolution about the y axis. The profile runs counter-clockwise around the solid's
/// cross-section in the (radius, height) half-plane (up the outside for a column). An open
/// profile is closed by flat caps at its ends, or by a single pole vertex where its radius is 0;
/// a looped profile (a torus) needs no caps. Optional sinusoidal flutes modulate the radius.
struct Lathe {
    std::vector<ProfilePoint> profile;
    std::uint32_t segments = 32;
    bool looped = false;
    std::uint32_t flutes = 0;
    float flute_depth = 0.0f;  // share of the radius removed at the bottom of a flute

    std::uint32_t vertex_count() const;
    std::size_t triangle_count() const;
    void emit(PartWriter& out) const;
};

/// Upright cylinder of radius r from y0 to y1 (a lathe with two profile points).
Lathe cylinder(float radius, float y0, float y1, std::uint32_t segments);
/// Torus around the y axis at height y: ring radius `major`, tube radius `minor`.
Lathe torus(float major, float minor, float y, std::uint32_t ring_segments, std::uint32_t tube_segments);

/// An arch in the xy-plane springing from y = 0 around the origin, extruded over z in
/// [-depth/2, depth/2]. The intrados is a half circle of `inner_radius`; the extrados is a half
/// circle of `outer_size`, or with `square_outer` the square [-outer_size, outer_size] x
/// [0, outer_size], which makes the arch the wall piece (arch plus spandrels) of an arcade bay.
struct Arch {
    float inner_radius = 1.0f;
    float outer_size = 1.2f;
    float depth = 0.5f;
    std::uint32_t segments = 32;  // a multiple of 4 puts the square's corners on vertices
    bool square_outer = false;

    std::uint32_t vertex_count() const { return 4 * (segments + 1); }
    std::size_t triangle_count() const { return 8 * std::size_t(segments) + 4; }
    void emit(PartWriter& out) const;
};

}  // namespace trident
