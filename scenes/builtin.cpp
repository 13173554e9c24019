#include "scenes/builtin.h"

#include <array>
#include <stdexcept>

#include "scenes/asteroid.h"
#include "scenes/bezier_teapot.h"
#include "scenes/city.h"
#include "scenes/hall.h"

namespace trident {

namespace {

constexpr std::uint32_t kTeapotSegments = 10;  // 10 x 10 quads a patch, as in the reference study
constexpr std::uint64_t kAsteroidSeed = 1;

Scene make_teapot_scene() {
    // Three-quarter view from the front right and above; light from the upper left so the spout,
    // lid and handle shade the body.
    return {"teapot", make_bezier_teapot(kTeapotSegments),
            CameraSpec{{2.6f, 3.9f, 6.4f}, {0.15f, 1.4f, 0.0f}, {0.0f, 1.0f, 0.0f}, 40.0f},
            PointLight{{-6.0f, 9.0f, 6.0f}}};
}

Scene make_asteroid_scene() {
    // Seen from slightly above; the light comes from the upper left, about 50 degrees off the
    // view, so crater rims cast shadows and the terminator runs across the right of the body.
    return {"asteroid", make_asteroid(kAsteroidFrequency, kAsteroidSeed),
            CameraSpec{{0.4f, 1.0f, 3.4f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 40.0f},
            PointLight{{-5.0f, 4.0f, 4.5f}}};
}

struct Entry {
    std::string_view name;
    std::string_view description;
    bool closed;
    std::size_t (*triangles)();
    Scene (*make)();
};

const std::array<Entry, 4> kEntries{{
    {"teapot", "Newell's Utah teapot, 32 Bezier patches at 10x10 quads (open: lid gap, spout and handle ends)", false,
     [] { return bezier_teapot_triangle_count(kTeapotSegments); }, make_teapot_scene},
    {"asteroid", "cratered asteroid: displaced geodesic sphere, closed and watertight", true,
     [] { return asteroid_triangle_count(kAsteroidFrequency); }, make_asteroid_scene},
    {"hall", "columned hall with arcades, coffered ceiling, tables, chairs and chandeliers, seen from inside", false,
     hall_triangle_count, make_hall_scene},
    {"city", "dense city blocks with windowed facades, cars, trees and lamps, seen from street level", false,
     city_triangle_count, make_city_scene},
}};

const Entry* find(std::string_view name) {
    for (const Entry& e : kEntries)
        if (e.name == name) return &e;
    return nullptr;
}

}  // namespace

std::vector<BuiltinSceneInfo> builtin_scenes() {
    std::vector<BuiltinSceneInfo> out;
    for (const Entry& e : kEntries)
        out.push_back({std::string(e.name), std::string(e.description), e.triangles(), e.closed});
    return out;
}

std::vector<std::string> builtin_scene_names() {
    std::vector<std::string> out;
    for (const Entry& e : kEntries) out.emplace_back(e.name);
    return out;
}

bool is_builtin_scene(std::string_view name) { return find(name) != nullptr; }

Scene make_builtin_scene(std::string_view name) {
    const Entry* e = find(name);
    if (e == nullptr) {
        std::string known;
        for (const Entry& k : kEntries) known += (known.empty() ? "" : ", ") + std::string(k.name);
        throw std::invalid_argument("unknown built-in scene '" + std::string(name) + "' (known: " + known + ")");
    }
    return e->make();
}

}  // namespace trident
