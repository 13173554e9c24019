#include "scenes/primitives.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace trident {

void Box::emit(PartWriter& out) const {
    // Corner i has x from bit 0, y from bit 1, z from bit 2 (0 = lo, 1 = hi).
    for (std::uint32_t i = 0; i < 8; ++i)
        out.vertex(i, {(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    // Each face as a quad, counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
    constexpr std::uint32_t kFaces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                            {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& f : kFaces) {
        out.triangle(f[0], f[1], f[2]);
        out.triangle(f[0], f[2], f[3]);
    }
}

namespace {

bool is_pole(const ProfilePoint& p) { return p.radius == 0.0f; }

/// Triangles of the band between two consecutive profile rings.
std::size_t band_triangles(const ProfilePoint& a, const ProfilePoint& b, std::uint32_t segments) {
    return (is_pole(a) || is_pole(b) ? 1 : 2) * std::size_t(segments);
}

}  // namespace

std::uint32_t Lathe::vertex_count() const {
    std::uint32_t count = 0;
    for (const ProfilePoint& p : profile) count += is_pole(p) ? 1 : segments;
    if (!looped) count += (is_pole(profile.front()) ? 0 : 1) + (is_pole(profile.back()) ? 0 : 1);
    return count;
}

std::size_t Lathe::triangle_count() const {
    std::size_t count = 0;
    for (std::size_t i = 0; i + 1 < profile.size(); ++i) count += band_triangles(profile[i], profile[i + 1], segments);
    if (looped) {
        count += band_triangles(profile.back(), profile.front(), segments);
    } else {
        count += (is_pole(profile.front()) ? 0 : segments) + (is_pole(profile.back()) ? 0 : segments);
    }
    return count;
}

void Lathe::emit(PartWriter& out) const {
    // Ring k direction (cos, -sin): with the profile counter-clockwise, quads (a, b, c, d) taken
    // around then up face outwards.
    std::vector<float> cos_theta(segments), sin_theta(segments), flute_scale(segments, 1.0f);
    for (std::uint32_t k = 0; k < segments; ++k) {
        const double theta = 2.0 * std::numbers::pi * k / segments;
        cos_theta[k] = float(std::cos(theta));
        sin_theta[k] = float(std::sin(theta));
        if (flutes > 0) flute_scale[k] = 1.0f - flute_depth * 0.5f * float(1.0 - std::cos(flutes * theta));
    }
    std::vector<std::uint32_t> ring_start(profile.size());
    std::uint32_t next = 0;
    for (std::size_t i = 0; i < profile.size(); ++i) {
        const ProfilePoint& p = profile[i];
        ring_start[i] = next;
        if (is_pole(p)) {
            out.vertex(next++, {0.0f, p.height, 0.0f});
            continue;
        }
        for (std::uint32_t k = 0; k < segments; ++k) {
            const float r = p.radius * flute_scale[k];
            out.vertex(next++, {r * cos_theta[k], p.height, -r * sin_theta[k]});
        }
    }
    auto band = [&](std::size_t i, std::size_t j) {
        for (std::uint32_t k = 0; k < segments; ++k) {
            const std::uint32_t k1 = (k + 1) % segments;
            if (is_pole(profile[i])) {
                out.triangle(ring_start[i], ring_start[j] + k1, ring_start[j] + k);
            } else if (is_pole(profile[j])) {
                out.triangle(ring_start[i] + k, ring_start[i] + k1, ring_start[j]);
            } else {
                const std::uint32_t a = ring_start[i] + k, b = ring_start[i] + k1;
                const std::uint32_t c = ring_start[j] + k1, d = ring_start[j] + k;
                out.triangle(a, b, c);
                out.triangle(a, c, d);
            }
        }
    };
    for (std::size_t i = 0; i + 1 < profile.size(); ++i) band(i, i + 1);
    if (looped) {
        band(profile.size() - 1, 0);
        return;
    }
    if (!is_pole(profile.front())) {  // the start cap faces down the profile's beginning
        const std::uint32_t center = next++;
        out.vertex(center, {0.0f, profile.front().height, 0.0f});
        for (std::uint32_t k = 0; k < segments; ++k) out.triangle(center, (k + 1) % segments, k);
    }
    if (!is_pole(profile.back())) {
        const std::uint32_t center = next++;
        const std::uint32_t ring = ring_start.back();
        out.vertex(center, {0.0f, profile.back().height, 0.0f});
        for (std::uint32_t k = 0; k < segments; ++k) out.triangle(center, ring + k, ring + (k + 1) % segments);
    }
}

Lathe cylinder(float radius, float y0, float y1, std::uint32_t segments) {
    return Lathe{{{radius, y0}, {radius, y1}}, segments};
}

Lathe torus(float major, float minor, float y, std::uint32_t ring_segments, std::uint32_t tube_segments) {
    Lathe ring{{}, ring_segments, true};
    for (std::uint32_t j = 0; j < tube_segments; ++j) {  // counter-clockwise around the tube
        const double phi = 2.0 * std::numbers::pi * j / tube_segments;
        ring.profile.push_back({major + minor * float(std::cos(phi)), y + minor * float(std::sin(phi))});
    }
    return ring;
}

void Arch::emit(PartWriter& out) const {
    // Vertices per step k: inner front, outer front, inner back, outer back.
    const float front = 0.5f * depth, back = -0.5f * depth;
    for (std::uint32_t k = 0; k <= segments; ++k) {
        const double theta = std::numbers::pi * k / segments;
        const double c = k == segments ? -1.0 : std::cos(theta), s = k == segments ? 0.0 : std::sin(theta);
        const double outer = square_outer ? outer_size / std::max(std::abs(c), s) : outer_size;
        const float ix = float(inner_radius * c), iy = float(inner_radius * s);
        const float ox = float(outer * c), oy = float(outer * s);
        out.vertex(4 * k + 0, {ix, iy, front});
        out.vertex(4 * k + 1, {ox, oy, front});
        out.vertex(4 * k + 2, {ix, iy, back});
        out.vertex(4 * k + 3, {ox, oy, back});
    }
    auto quad = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
        out.triangle(a, b, c);
        out.triangle(a, c, d);
    };
    for (std::uint32_t k = 0; k < segments; ++k) {
        const std::uint32_t v = 4 * k, w = 4 * (k + 1);
        quad(v + 0, v + 1, w + 1, w + 0);  // front face
        quad(v + 2, w + 2, w + 3, v + 3);  // back face
        quad(v + 1, v + 3, w + 3, w + 1);  // extrados
        quad(v + 0, w + 0, w + 2, v + 2);  // intrados
    }
    const std::uint32_t last = 4 * segments;
    quad(0, 2, 3, 1);                              // springing at +x
    quad(last + 0, last + 1, last + 3, last + 2);  // springing at -x
}

}  // namespace trident
