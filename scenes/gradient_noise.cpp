#include "scenes/gradient_noise.h"

#include <cmath>

#include "scenes/hash_random.h"

namespace trident {

namespace {

std::uint64_t lattice_hash(std::uint64_t seed, std::int64_t x, std::int64_t y, std::int64_t z) {
    return hash_combine(hash_combine(hash_combine(seed, std::uint64_t(x)), std::uint64_t(y)), std::uint64_t(z));
}

/// dot(g, d) for the gradient g picked by the hash among the 12 directions to cube edge midpoints.
float gradient_dot(std::uint64_t hash, float dx, float dy, float dz) {
    switch ((hash >> 32) % 12) {
        case 0:
            return dx + dy;
        case 1:
            return -dx + dy;
        case 2:
            return dx - dy;
        case 3:
            return -dx - dy;
        case 4:
            return dx + dz;
        case 5:
            return -dx + dz;
        case 6:
            return dx - dz;
        case 7:
            return -dx - dz;
        case 8:
            return dy + dz;
        case 9:
            return -dy + dz;
        case 10:
            return dy - dz;
        default:
            return -dy - dz;
    }
}

float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
float lerp(float a, float b, float t) { return a + t * (b - a); }

}  // namespace

float gradient_noise(const Vec3f& p, std::uint64_t seed) {
    const float fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
    const auto ix = std::int64_t(fx), iy = std::int64_t(fy), iz = std::int64_t(fz);
    const float dx = p.x - fx, dy = p.y - fy, dz = p.z - fz;
    float corner[8];
    for (int c = 0; c < 8; ++c) {
        const int ox = c & 1, oy = (c >> 1) & 1, oz = (c >> 2) & 1;
        corner[c] =
            gradient_dot(lattice_hash(seed, ix + ox, iy + oy, iz + oz), dx - float(ox), dy - float(oy), dz - float(oz));
    }
    const float u = fade(dx), v = fade(dy), w = fade(dz);
    const float x00 = lerp(corner[0], corner[1], u), x10 = lerp(corner[2], corner[3], u);
    const float x01 = lerp(corner[4], corner[5], u), x11 = lerp(corner[6], corner[7], u);
    return lerp(lerp(x00, x10, v), lerp(x01, x11, v), w);
}

float fractal_noise(const Vec3f& p, int octaves, std::uint64_t seed) {
    float sum = 0.0f, amplitude = 1.0f, total = 0.0f, frequency = 1.0f;
    for (int o = 0; o < octaves; ++o) {
        sum += amplitude * gradient_noise(p * frequency, hash_combine(seed, std::uint64_t(o)));
        total += amplitude;
        amplitude *= 0.5f;
        frequency *= 2.0f;
    }
    return sum / total;
}

}  // namespace trident
