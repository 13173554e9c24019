#include "accel/any_accel.h"

#include <fmt/format.h>

#include <stdexcept>

namespace trident {

const char* to_string(AccelKind kind) {
    switch (kind) {
        case AccelKind::brute: return "brute";
        case AccelKind::bvh: return "bvh";
        case AccelKind::kdtree: return "kdtree";
        case AccelKind::octree: return "octree";
    }
    return "?";
}

std::optional<AccelKind> parse_accel_kind(std::string_view name) {
    for (AccelKind kind : {AccelKind::brute, AccelKind::bvh, AccelKind::kdtree, AccelKind::octree})
        if (name == to_string(kind)) return kind;
    return std::nullopt;
}

bool is_built(AccelKind kind) { return kind == AccelKind::brute; }

std::vector<AccelKind> built_accel_kinds() {
    std::vector<AccelKind> kinds;
    for (AccelKind kind : {AccelKind::brute, AccelKind::bvh, AccelKind::kdtree, AccelKind::octree})
        if (is_built(kind)) kinds.push_back(kind);
    return kinds;
}

AnyAccel AnyAccel::build(AccelKind kind, const Mesh& mesh, const AccelOptions&) {
    switch (kind) {
        case AccelKind::brute: return AnyAccel(kind, BruteForce::build(mesh));
        default: break;
    }
    throw std::invalid_argument(fmt::format("--accel {}: not built yet", to_string(kind)));
}

}  // namespace trident
