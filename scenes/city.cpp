#include "scenes/city.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "scenes/hash_random.h"

namespace trident {

namespace {

// Avenues run along z at x = kAvenuePitch * i, cross streets along x at z = -kStreetPitch * j.
// Block (i, j) lies between avenues i and i + 1 and cross streets j and j + 1.
constexpr int kBlockColumns = 4;  // avenue gaps, centred on the avenue at x = 0
constexpr int kBlockRows = 11;    // cross-street gaps, going away from the camera (-z)
constexpr float kAvenuePitch = 60.0f;
constexpr float kStreetPitch = 80.0f;
constexpr float kStreetWidth = 20.0f;  // kerb to kerb 14 m, plus 3 m of sidewalk each side
constexpr float kSidewalk = 3.0f;
constexpr float kFloorHeight = 3.5f;

float avenue_x(int i) { return kAvenuePitch * float(i - kBlockColumns / 2); }
float street_z(int j) { return -kStreetPitch * float(j); }

/// One side of a building: the wall plane through `center` (at ground level) facing `normal`,
/// `width` wide along `along` (which is up x normal, so the frame keeps its handedness).
struct Facade {
    Vec3f center, along, normal;
    float width;
};

/// A window on every floor and every 2.6 m or so of the facade, each a box standing 12 cm proud.
void add_windows(MeshBuilder& b, const Facade& f, float base, int floors, HashRandom& rng) {
    const int columns = std::max(1, int(f.width / 2.6f));
    const float pitch = f.width / float(columns);
    const float window_width = std::min(1.5f, 0.6f * pitch) * rng.uniform(0.9f, 1.1f);
    const float window_height = 1.7f * rng.uniform(0.9f, 1.1f);
    const Affine frame{f.along, {0.0f, 1.0f, 0.0f}, f.normal, f.center};  // local x along, z out
    for (int floor = 0; floor < floors; ++floor) {
        const float y = base + kFloorHeight * float(floor) + 0.9f;
        for (int c = 0; c < columns; ++c) {
            const float x = -0.5f * f.width + pitch * (float(c) + 0.5f);
            b.add(Box{{x - 0.5f * window_width, y, -0.05f}, {x + 0.5f * window_width, y + window_height, 0.12f}},
                  frame);
        }
    }
}

/// A building of `floors` storeys on the footprint [lo, hi] (x, z), from height `base` up: a box,
/// a ledge at every floor, windows on all four sides.
void add_storeys(MeshBuilder& b, Vec3f lo, Vec3f hi, float base, int floors, HashRandom& rng) {
    const float top = base + kFloorHeight * float(floors);
    b.add(Box{{lo.x, base, lo.z}, {hi.x, top, hi.z}});
    for (int floor = 1; floor <= floors; ++floor) {
        const float y = base + kFloorHeight * float(floor);
        b.add(Box{{lo.x - 0.15f, y - 0.25f, lo.z - 0.15f}, {hi.x + 0.15f, y, hi.z + 0.15f}});
    }
    const float cx = 0.5f * (lo.x + hi.x), cz = 0.5f * (lo.z + hi.z);
    const float wx = hi.x - lo.x, wz = hi.z - lo.z;
    add_windows(b, {{cx, 0.0f, hi.z}, {1, 0, 0}, {0, 0, 1}, wx}, base, floors, rng);
    add_windows(b, {{cx, 0.0f, lo.z}, {-1, 0, 0}, {0, 0, -1}, wx}, base, floors, rng);
    add_windows(b, {{hi.x, 0.0f, cz}, {0, 0, -1}, {1, 0, 0}, wz}, base, floors, rng);
    add_windows(b, {{lo.x, 0.0f, cz}, {0, 0, 1}, {-1, 0, 0}, wz}, base, floors, rng);
}

/// One building on a lot: storeys, sometimes a set-back tower, a water tank or a stair hut.
void add_building(MeshBuilder& b, Vec3f lot_lo, Vec3f lot_hi, HashRandom& rng) {
    const float margin = rng.uniform(0.5f, 2.0f);
    Vec3f lo = lot_lo + Vec3f{margin, 0.0f, margin}, hi = lot_hi - Vec3f{margin, 0.0f, margin};
    int floors = 3 + int(rng.below(10)) + (rng.uniform() < 0.35f ? int(rng.below(16)) : 0);
    add_storeys(b, lo, hi, 0.0f, floors, rng);
    float roof = kFloorHeight * float(floors);
    if (floors > 8 && rng.uniform() < 0.6f) {
        const float inset = rng.uniform(2.0f, 4.0f);
        lo = lo + Vec3f{inset, 0.0f, inset};
        hi = hi - Vec3f{inset, 0.0f, inset};
        const int upper = 2 + int(rng.below(8));
        add_storeys(b, lo, hi, roof, upper, rng);
        roof += kFloorHeight * float(upper);
    }
    const Vec3f c{rng.uniform(lo.x + 2.5f, hi.x - 2.5f), roof, rng.uniform(lo.z + 2.5f, hi.z - 2.5f)};
    if (rng.uniform() < 0.5f) {
        b.add(Lathe{{{1.3f, 3.0f}, {1.3f, 5.2f}, {0.9f, 5.9f}, {0.0f, 6.2f}}, 20}, translation(c));
        for (int i = 0; i < 4; ++i) {
            const float a = 0.5f * kPi * float(i) + 0.25f * kPi;
            b.add(Box{{-0.08f, 0.0f, -0.08f}, {0.08f, 3.0f, 0.08f}},
                  translation(c + Vec3f{std::cos(a), 0.0f, std::sin(a)}));
        }
    } else {
        b.add(Box{{-1.5f, 0.0f, -1.2f}, {1.5f, 2.6f, 1.2f}}, translation(c));
    }
}

void add_car(MeshBuilder& b, const Affine& at, HashRandom& rng) {
    const float length = rng.uniform(3.8f, 4.8f), half = 0.5f * length;
    b.add(Box{{-half, 0.3f, -0.85f}, {half, 0.95f, 0.85f}}, at);
    b.add(Box{{-0.3f * length, 0.95f, -0.75f}, {0.2f * length, 1.45f, 0.75f}}, at);
    for (float x : {-0.32f * length, 0.32f * length})
        for (float z : {-0.8f, 0.8f})  // wheels: cylinders turned to lie along z
            b.add(cylinder(0.32f, -0.12f, 0.12f, 14), at * translation({x, 0.32f, z}) * rotation_x(0.5f * kPi));
}

void add_tree(MeshBuilder& b, const Vec3f& foot, HashRandom& rng) {
    const float height = rng.uniform(3.0f, 4.5f), crown = rng.uniform(1.4f, 2.0f);
    b.add(Lathe{{{0.2f, 0.0f}, {0.14f, height}}, 8}, translation(foot));
    b.add(GeodesicSphere{3}, translation(foot + Vec3f{0.0f, height + 0.6f * crown, 0.0f}) *
                                 scaling({crown, 1.2f * crown, crown}) * rotation_y(rng.uniform(0.0f, 2.0f * kPi)));
}

void add_lamp(MeshBuilder& b, const Vec3f& foot, float toward_road) {
    b.add(Lathe{{{0.14f, 0.0f}, {0.1f, 0.6f}, {0.07f, 0.7f}, {0.06f, 6.0f}}, 12}, translation(foot));
    b.add(Box{{std::min(0.0f, toward_road * 1.4f), 5.85f, -0.04f}, {std::max(0.0f, toward_road * 1.4f), 5.95f, 0.04f}},
          translation(foot));
    b.add(Box{{toward_road * 1.4f - 0.3f, 5.7f, -0.15f}, {toward_road * 1.4f + 0.3f, 5.85f, 0.15f}}, translation(foot));
}

/// Street life along one side of an avenue: trees and lamps on the sidewalk, parked cars in the
/// lane by the kerb. `kerb_x` is the kerb line, `toward_road` is +1 or -1.
void add_avenue_side(MeshBuilder& b, float kerb_x, float toward_road, float z0, float z1, HashRandom& rng) {
    const int slots = int((z1 - z0 - 10.0f) / 12.0f) + 1;  // every 12 m, 6 m in from each end
    for (int k = 0; k < slots; ++k) {
        const float z = z0 + 6.0f + 12.0f * float(k);
        if (rng.uniform() < 0.8f) add_tree(b, {kerb_x - toward_road * 1.2f, 0.15f, z}, rng);
        if (k % 2 == 0) add_lamp(b, {kerb_x - toward_road * 0.5f, 0.15f, z + 6.0f}, toward_road);
    }
    for (float z = z0 + 3.0f; z < z1 - 5.0f; z += rng.uniform(5.5f, 8.0f)) {
        if (rng.uniform() < 0.3f) continue;
        const float turn = rng.uniform(-0.05f, 0.05f) + 0.5f * kPi;  // cars lie along z
        add_car(b, translation({kerb_x + toward_road * 1.3f, 0.0f, z + 2.5f}) * rotation_y(turn), rng);
    }
}

void add_block(MeshBuilder& b, int i, int j) {
    HashRandom rng(hash_combine(0xC17E, std::uint64_t(i * 1000 + j)));
    const float x0 = avenue_x(i) + 0.5f * kStreetWidth, x1 = avenue_x(i + 1) - 0.5f * kStreetWidth;
    const float z1 = street_z(j) - 0.5f * kStreetWidth, z0 = street_z(j + 1) + 0.5f * kStreetWidth;
    b.add(Box{{x0, 0.0f, z0}, {x1, 0.15f, z1}});  // the sidewalk slab the block stands on
    const Vec3f lo{x0 + kSidewalk, 0.15f, z0 + kSidewalk}, hi{x1 - kSidewalk, 0.15f, z1 - kSidewalk};
    constexpr int kLotsX = 2, kLotsZ = 3;
    const float lot_x = (hi.x - lo.x) / kLotsX, lot_z = (hi.z - lo.z) / kLotsZ;
    for (int a = 0; a < kLotsX; ++a)
        for (int c = 0; c < kLotsZ; ++c) {
            const Vec3f lot_lo{lo.x + lot_x * float(a), 0.0f, lo.z + lot_z * float(c)};
            add_building(b, lot_lo, lot_lo + Vec3f{lot_x, 0.0f, lot_z}, rng);
        }
    add_avenue_side(b, x0, -1.0f, z0, z1, rng);
    add_avenue_side(b, x1, 1.0f, z0, z1, rng);
}

/// Dashed centre lines down every avenue, 3 m dashes every 9 m.
void add_road_markings(MeshBuilder& b) {
    const float z_far = street_z(kBlockRows), z_near = street_z(0) + 0.5f * kStreetWidth - 2.0f;
    const int dashes = int((z_near - z_far) / 9.0f) + 1;
    for (int i = 0; i <= kBlockColumns; ++i) {
        const float x = avenue_x(i);
        for (int k = 0; k < dashes; ++k) {
            const float z = z_near - 9.0f * float(k);
            b.add(Box{{x - 0.15f, 0.0f, z - 3.0f}, {x + 0.15f, 0.01f, z}});
        }
    }
}

}  // namespace

MeshBuilder city_parts() {
    MeshBuilder b;
    const float margin = kStreetWidth;
    b.add(Box{{avenue_x(0) - margin, -0.5f, street_z(kBlockRows) - margin},
              {avenue_x(kBlockColumns) + margin, 0.0f, street_z(0) + margin}});
    add_road_markings(b);
    for (int j = 0; j < kBlockRows; ++j)
        for (int i = 0; i < kBlockColumns; ++i) add_block(b, i, j);
    return b;
}

std::size_t city_triangle_count() { return city_parts().triangle_count(); }

Scene make_city_scene() {
    // Standing in the avenue at x = 0, a little right of the centre line, looking down it and
    // slightly up: facades fill both sides. The light is high in the west, so the east side's
    // facades are lit while the west side's buildings throw their shadows across the street.
    return {"city", city_parts().build(),
            CameraSpec{{3.0f, 1.7f, -14.0f}, {-1.0f, 16.0f, -200.0f}, {0.0f, 1.0f, 0.0f}, 60.0f},
            PointLight{{-150.0f, 350.0f, 60.0f}}};
}

}  // namespace trident
