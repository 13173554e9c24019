#include "scenes/hall.h"

#include <cmath>
#include <numbers>

#include "scenes/hash_random.h"

namespace trident {

namespace {

// The hall's interior spans x in [-12, 12], z in [-30, 30], floor at y = 0, ceiling at y = 13.
constexpr float kHalfWidth = 12.0f, kHalfLength = 30.0f, kCeiling = 13.0f;
constexpr float kArcadeX = 6.0f;                    // the two arcades stand at x = +-6
constexpr int kBays = 12;                           // arcade bays along the hall
constexpr float kBay = 2.0f * kHalfLength / kBays;  // 5 m: column spacing along z
constexpr int kTables = 6;                          // tables in each of the two rows
constexpr float kSpringing = 7.85f;                 // top of the column abacus, where the arches start
constexpr float kAbacusHalf = 0.78f;

/// z of the columns (k = 1 .. kBays - 1) and of the bay centres (k + 0.5).
float bay_z(float k) { return -kHalfLength + kBay * k; }
/// z of the middle of table k (and of the chandelier above it), 8 m apart.
float table_z(int k) { return -20.0f + 8.0f * float(k); }

void add_floor_and_shell(MeshBuilder& b) {
    b.add(Box{{-kHalfWidth - 0.5f, -0.5f, -kHalfLength - 0.5f}, {kHalfWidth + 0.5f, -0.02f, kHalfLength + 0.5f}});
    // Floor tiles 1.2 m apart with 3 cm joints.
    constexpr int kTilesX = 20, kTilesZ = 50;
    constexpr float tile = 2.0f * kHalfWidth / kTilesX, joint = 0.015f;
    for (int i = 0; i < kTilesX; ++i)
        for (int k = 0; k < kTilesZ; ++k) {
            const float x = -kHalfWidth + tile * float(i), z = -kHalfLength + tile * float(k);
            b.add(Box{{x + joint, -0.02f, z + joint}, {x + tile - joint, 0.0f, z + tile - joint}});
        }
    const float top = kCeiling + 0.5f;
    for (float side : {-1.0f, 1.0f}) {
        b.add(Box{{side > 0 ? kHalfWidth : -kHalfWidth - 0.5f, 0.0f, -kHalfLength - 0.5f},
                  {side > 0 ? kHalfWidth + 0.5f : -kHalfWidth, top, kHalfLength + 0.5f}});
        b.add(Box{{-kHalfWidth, 0.0f, side > 0 ? kHalfLength : -kHalfLength - 0.5f},
                  {kHalfWidth, top, side > 0 ? kHalfLength + 0.5f : -kHalfLength}});
    }
    b.add(Box{{-kHalfWidth, kCeiling, -kHalfLength}, {kHalfWidth, top, kHalfLength}});
}

/// Beams every 2 m both ways; each coffer has a stepped inner frame and a rosette.
void add_coffered_ceiling(MeshBuilder& b) {
    constexpr int kCoffersX = 12, kCoffersZ = 30;
    constexpr float pitch = 2.0f * kHalfWidth / kCoffersX, beam = 0.15f, beam_bottom = kCeiling - 0.5f;
    for (int i = 0; i <= kCoffersX; ++i) {
        const float x = -kHalfWidth + pitch * float(i);
        b.add(Box{{x - beam, beam_bottom, -kHalfLength}, {x + beam, kCeiling, kHalfLength}});
    }
    for (int k = 0; k <= kCoffersZ; ++k) {
        const float z = -kHalfLength + pitch * float(k);
        b.add(Box{{-kHalfWidth, beam_bottom, z - beam}, {kHalfWidth, kCeiling, z + beam}});
    }
    const float outer = 0.5f * pitch - beam, inner = outer - 0.2f, frame_bottom = kCeiling - 0.25f;
    for (int i = 0; i < kCoffersX; ++i)
        for (int k = 0; k < kCoffersZ; ++k) {
            const float x = -kHalfWidth + pitch * (float(i) + 0.5f), z = -kHalfLength + pitch * (float(k) + 0.5f);
            b.add(Box{{x - outer, frame_bottom, z - outer}, {x + outer, kCeiling, z - inner}});
            b.add(Box{{x - outer, frame_bottom, z + inner}, {x + outer, kCeiling, z + outer}});
            b.add(Box{{x - outer, frame_bottom, z - inner}, {x - inner, kCeiling, z + inner}});
            b.add(Box{{x + inner, frame_bottom, z - inner}, {x + outer, kCeiling, z + inner}});
            b.add(GeodesicSphere{3}, translation({x, kCeiling, z}) * scaling({0.3f, 0.14f, 0.3f}));
        }
}

/// A fluted column with entasis on a square plinth, with a moulded base and a Doric-like capital.
void add_column(MeshBuilder& b, const Vec3f& foot) {
    const Affine at = translation(foot);
    b.add(Box{{-0.7f, 0.0f, -0.7f}, {0.7f, 0.35f, 0.7f}}, at);
    b.add(Lathe{{{0.62f, 0.35f},
                 {0.64f, 0.42f},
                 {0.62f, 0.5f},
                 {0.55f, 0.55f},
                 {0.52f, 0.62f},
                 {0.56f, 0.68f},
                 {0.5f, 0.75f}},
                64},
          at);
    Lathe shaft{{}, 96, false, 24, 0.05f};
    constexpr int kRings = 20;
    for (int i = 0; i <= kRings; ++i) {
        const float t = float(i) / kRings;  // entasis: the shaft swells a little, then narrows
        shaft.profile.push_back({0.47f + 0.02f * std::sin(kPi * t) - 0.05f * t, 0.75f + 6.25f * t});
    }
    b.add(std::move(shaft), at);
    b.add(Lathe{{{0.44f, 7.0f},
                 {0.47f, 7.08f},
                 {0.5f, 7.12f},
                 {0.5f, 7.18f},
                 {0.45f, 7.22f},
                 {0.48f, 7.32f},
                 {0.58f, 7.45f},
                 {0.7f, 7.55f},
                 {0.72f, 7.6f}},
                64},
          at);
    b.add(Box{{-kAbacusHalf, 7.6f, -kAbacusHalf}, {kAbacusHalf, kSpringing, kAbacusHalf}}, at);
}

/// Two arcades: columns, arch-and-spandrel pieces between them, a clerestory wall above, and
/// half-pilasters where each arcade meets an end wall.
void add_arcades(MeshBuilder& b) {
    const float half_bay = 0.5f * kBay;
    for (float x : {-kArcadeX, kArcadeX}) {
        for (int k = 1; k < kBays; ++k) add_column(b, {x, 0.0f, bay_z(float(k))});
        for (int k = 0; k < kBays; ++k)
            b.add(Arch{half_bay - kAbacusHalf, half_bay, 1.0f, 64, true},
                  translation({x, kSpringing, bay_z(float(k) + 0.5f)}) * rotation_y(0.5f * kPi));
        b.add(Box{{x - 0.5f, kSpringing + half_bay, -kHalfLength}, {x + 0.5f, kCeiling, kHalfLength}});
        for (float end : {-kHalfLength, kHalfLength})
            b.add(
                Box{{x - 0.6f, 0.0f, end > 0 ? end - 0.3f : end}, {x + 0.6f, kSpringing, end > 0 ? end : end + 0.3f}});
    }
}

/// Pilasters and blind arches on the aisle walls, a dais and a great blind arch on the far wall.
void add_wall_relief(MeshBuilder& b) {
    for (float side : {-1.0f, 1.0f}) {
        const float wall = side * kHalfWidth;
        for (int k = 1; k < kBays; ++k) {
            const float z = bay_z(float(k));
            b.add(Box{{side > 0 ? wall - 0.3f : wall, 0.0f, z - 0.4f},
                      {side > 0 ? wall : wall + 0.3f, kCeiling, z + 0.4f}});
        }
        for (int k = 0; k < kBays; ++k)
            b.add(Arch{1.6f, 2.0f, 0.3f, 48, false},
                  translation({wall - side * 0.15f, 5.0f, bay_z(float(k) + 0.5f)}) * rotation_y(0.5f * kPi));
    }
    b.add(Box{{-5.0f, 0.0f, -kHalfLength}, {5.0f, 0.3f, -kHalfLength + 4.0f}});
    b.add(Box{{-4.0f, 0.3f, -kHalfLength}, {4.0f, 0.6f, -kHalfLength + 3.0f}});
    b.add(Arch{3.0f, 3.8f, 0.4f, 96, true}, translation({0.0f, 4.5f, -kHalfLength + 0.2f}));
}

/// A chair facing +x, with its seat centred on the origin's vertical.
void add_chair(MeshBuilder& b, const Affine& at) {
    b.add(Box{{-0.22f, 0.43f, -0.22f}, {0.22f, 0.48f, 0.22f}}, at);
    for (float x : {-0.19f, 0.16f})
        for (float z : {-0.19f, 0.16f}) b.add(Box{{x, 0.0f, z}, {x + 0.035f, 0.43f, z + 0.035f}}, at);
    for (float z : {-0.21f, 0.17f}) b.add(Box{{-0.22f, 0.48f, z}, {-0.185f, 0.98f, z + 0.04f}}, at);
    for (float y : {0.66f, 0.86f}) b.add(Box{{-0.215f, y, -0.17f}, {-0.19f, y + 0.1f, 0.17f}}, at);
}

/// Two rows of long tables down the nave with chairs on both sides, slightly out of line.
void add_tables_and_chairs(MeshBuilder& b) {
    HashRandom rng(0x4a11);
    for (float x : {-2.4f, 2.4f})
        for (int k = 0; k < kTables; ++k) {
            const Affine at = translation({x, 0.0f, table_z(k)});
            b.add(Box{{-0.55f, 0.72f, -2.0f}, {0.55f, 0.78f, 2.0f}}, at);
            for (float lx : {-0.45f, 0.45f})
                for (float lz : {-1.85f, 1.85f})
                    b.add(cylinder(0.04f, 0.0f, 0.72f, 16), at * translation({lx, 0.0f, lz}));
            for (float side : {-1.0f, 1.0f})
                for (float cz : {-1.3f, 0.0f, 1.3f}) {
                    const float turn = (side > 0 ? kPi : 0.0f) + rng.uniform(-0.12f, 0.12f);
                    const Vec3f seat{side * (0.85f + rng.uniform(0.0f, 0.15f)), 0.0f, cz + rng.uniform(-0.08f, 0.08f)};
                    add_chair(b, at * translation(seat) * rotation_y(turn));
                }
        }
    for (float x : {-10.4f, 10.4f})  // benches along the aisle walls
        for (int k = 0; k < kBays; ++k) {
            const Affine at = translation({x, 0.0f, bay_z(float(k) + 0.5f)});
            b.add(Box{{-0.25f, 0.42f, -1.8f}, {0.25f, 0.48f, 1.8f}}, at);
            for (float lz : {-1.6f, 1.5f}) b.add(Box{{-0.22f, 0.0f, lz}, {0.22f, 0.42f, lz + 0.1f}}, at);
        }
}

/// A ring chandelier hanging from the ceiling: rod, boss, ring, chains, candles and flames.
void add_chandelier(MeshBuilder& b, const Vec3f& center) {
    const Affine at = translation(center);
    b.add(cylinder(0.025f, 0.0f, kCeiling - center.y, 8), at);
    b.add(GeodesicSphere{4}, at * scaling({0.14f, 0.2f, 0.14f}));
    b.add(torus(0.8f, 0.035f, 0.0f, 48, 8), at);
    constexpr int kCandles = 12;
    for (int i = 0; i < kCandles; ++i) {
        const float a = 2.0f * kPi * (float(i) + 0.5f) / kCandles;
        const Vec3f p{0.8f * std::cos(a), 0.0f, 0.8f * std::sin(a)};
        b.add(cylinder(0.025f, 0.03f, 0.22f, 8), at * translation(p));
        b.add(GeodesicSphere{2}, at * translation(p + Vec3f{0.0f, 0.27f, 0.0f}) * scaling({0.025f, 0.05f, 0.025f}));
    }
    for (int i = 0; i < 4; ++i) {  // chains from the ring up to the rod
        const float a = 0.5f * kPi * float(i);
        const Vec3f foot{0.8f * std::cos(a), 0.0f, 0.8f * std::sin(a)};
        const Vec3f along = Vec3f{0.0f, 0.9f, 0.0f} - foot;
        b.add(cylinder(0.012f, 0.0f, length(along), 6), at * translation(foot) * y_along(along));
    }
}

}  // namespace

MeshBuilder hall_parts() {
    MeshBuilder b;
    add_floor_and_shell(b);
    add_coffered_ceiling(b);
    add_arcades(b);
    add_wall_relief(b);
    add_tables_and_chairs(b);
    for (float x : {-2.4f, 2.4f})
        for (int k = 0; k < kTables; ++k) add_chandelier(b, {x, 6.2f, table_z(k)});
    return b;
}

std::size_t hall_triangle_count() { return hall_parts().triangle_count(); }

Scene make_hall_scene() {
    // Eye height near the entrance wall, looking down the nave and a little up so floor, tables,
    // both arcades and the coffers share the frame. The light hangs high in the nave, ahead of
    // the camera between two chandeliers: it lights the column faces the camera sees, and
    // columns, chairs and chandeliers cast shadows on the floor, the tables and the aisles.
    return {"hall", hall_parts().build(),
            CameraSpec{{1.2f, 1.7f, 27.0f}, {-0.8f, 4.2f, 0.0f}, {0.0f, 1.0f, 0.0f}, 60.0f},
            PointLight{{3.5f, 11.0f, 16.0f}}};
}

}  // namespace trident
