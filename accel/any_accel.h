#pragma once
// One value holding whichever structure a run chose, so the renderer and the benchmark are
// written once: `accel.visit([&](const auto& structure) { ... })` hands over the concrete type
// and every traversal inlines into the caller's loop. Header-only: it is compiled where it is used,
// above the structures' libraries.
#include <fmt/format.h>

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "accel/brute/brute_force.h"
#include "core/mesh.h"
#include "accel/bvh/bvh.h"
#include "accel/bvh/wide_bvh.h"
#include "accel/kdtree/kdtree.h"
#include "accel/octree/octree.h"
#include "simd/packet.h"

namespace trident {

/// bvh: the wide BVH (BvhOptions::width children a node; width 2 is the binary tree); bvh2: the
/// binary BVH whatever the width, the reference study's structure, kept beside the wide one.
enum class AccelKind { brute, bvh, bvh2, kdtree, octree };

/// Each structure's build options; a run uses the one its kind names.
struct AccelOptions {
    BvhOptions bvh;
    KdTreeOptions kdtree;
    OctreeOptions octree;
};

class AnyAccel {
public:
    /// Throws std::invalid_argument when the structure is not built into this binary.
    static AnyAccel build(AccelKind kind, const Mesh& mesh, const AccelOptions& options = {});

    template <class F>
    decltype(auto) visit(F&& f) const { return std::visit(std::forward<F>(f), structure_); }
    const AccelStats& stats() const {
        return std::visit([](const auto& s) -> const AccelStats& { return s.stats(); }, structure_);
    }
    AccelKind kind() const { return kind_; }

private:
    using Structure = std::variant<BruteForce, Bvh, WideBvh<4, 4>, WideBvh<8, 4>, WideBvh<16, 4>, KdTree, Octree>;
    AnyAccel(AccelKind kind, Structure structure) : kind_(kind), structure_(std::move(structure)) {}
    AccelKind kind_;
    Structure structure_;
};

inline const char* to_string(AccelKind kind) {
    switch (kind) {
        case AccelKind::brute: return "brute";
        case AccelKind::bvh: return "bvh";
        case AccelKind::bvh2: return "bvh2";
        case AccelKind::kdtree: return "kdtree";
        case AccelKind::octree: return "octree";
    }
    return "?";
}

inline std::optional<AccelKind> parse_accel_kind(std::string_view name) {
    for (AccelKind kind : {AccelKind::brute, AccelKind::bvh, AccelKind::bvh2, AccelKind::kdtree, AccelKind::octree})
        if (name == to_string(kind)) return kind;
    return std::nullopt;
}


inline std::vector<AccelKind> built_accel_kinds() {
    return {AccelKind::brute, AccelKind::bvh, AccelKind::bvh2, AccelKind::kdtree, AccelKind::octree};
}

inline AnyAccel AnyAccel::build(AccelKind kind, const Mesh& mesh, const AccelOptions& options) {
    switch (kind) {
        case AccelKind::brute: return AnyAccel(kind, BruteForce::build(mesh));
        case AccelKind::bvh:
            options.bvh.validate();
            switch (options.bvh.width) {
                case 4: return AnyAccel(kind, WideBvh<4, 4>::build(mesh, options.bvh));
                case 8: return AnyAccel(kind, WideBvh<8, 4>::build(mesh, options.bvh));
                case 16: return AnyAccel(kind, WideBvh<16, 4>::build(mesh, options.bvh));
                default: return AnyAccel(kind, Bvh::build(mesh, options.bvh));  // width 2
            }
        case AccelKind::bvh2: return AnyAccel(kind, Bvh::build(mesh, options.bvh));
        case AccelKind::kdtree: return AnyAccel(kind, KdTree::build(mesh, options.kdtree));
        case AccelKind::octree: return AnyAccel(kind, Octree::build(mesh, options.octree));
    }
    throw std::invalid_argument(fmt::format("unknown structure {}", int(kind)));
}

}  // namespace trident
