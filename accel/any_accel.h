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
#ifdef TRIDENT_HAVE_BVH
#include "accel/bvh/bvh.h"
#endif
#ifdef TRIDENT_HAVE_KDTREE
#include "accel/kdtree/kdtree.h"
#endif
#ifdef TRIDENT_HAVE_OCTREE
#include "accel/octree/octree.h"
#endif

namespace trident {

enum class AccelKind { brute, bvh, kdtree, octree };


/// Each structure's build options; a run uses the one its kind names.
struct AccelOptions {
#ifdef TRIDENT_HAVE_BVH
    BvhOptions bvh;
#endif
#ifdef TRIDENT_HAVE_KDTREE
    KdTreeOptions kdtree;
#endif
#ifdef TRIDENT_HAVE_OCTREE
    OctreeOptions octree;
#endif
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
    using Structure = std::variant<BruteForce
#ifdef TRIDENT_HAVE_BVH
                                   , Bvh
#endif
#ifdef TRIDENT_HAVE_KDTREE
                                   , KdTree
#endif
#ifdef TRIDENT_HAVE_OCTREE
                                   , Octree
#endif
                                   >;
    AnyAccel(AccelKind kind, Structure structure) : kind_(kind), structure_(std::move(structure)) {}
    AccelKind kind_;
    Structure structure_;
};

/// Whether this binary contains the structure.
inline const char* to_string(AccelKind kind) {
    switch (kind) {
        case AccelKind::brute: return "brute";
        case AccelKind::bvh: return "bvh";
        case AccelKind::kdtree: return "kdtree";
        case AccelKind::octree: return "octree";
    }
    return "?";
}

inline std::optional<AccelKind> parse_accel_kind(std::string_view name) {
    for (AccelKind kind : {AccelKind::brute, AccelKind::bvh, AccelKind::kdtree, AccelKind::octree})
        if (name == to_string(kind)) return kind;
    return std::nullopt;
}

inline bool is_built(AccelKind kind) {
    switch (kind) {
        case AccelKind::brute: return true;
#ifdef TRIDENT_HAVE_BVH
        case AccelKind::bvh: return true;
#endif
#ifdef TRIDENT_HAVE_KDTREE
        case AccelKind::kdtree: return true;
#endif
#ifdef TRIDENT_HAVE_OCTREE
        case AccelKind::octree: return true;
#endif
        default: return false;
    }
}

inline std::vector<AccelKind> built_accel_kinds() {
    std::vector<AccelKind> kinds;
    for (AccelKind kind : {AccelKind::brute, AccelKind::bvh, AccelKind::kdtree, AccelKind::octree})
        if (is_built(kind)) kinds.push_back(kind);
    return kinds;
}

inline AnyAccel AnyAccel::build(AccelKind kind, const Mesh& mesh, [[maybe_unused]] const AccelOptions& options) {
    switch (kind) {
        case AccelKind::brute: return AnyAccel(kind, BruteForce::build(mesh));
#ifdef TRIDENT_HAVE_BVH
        case AccelKind::bvh: return AnyAccel(kind, Bvh::build(mesh, options.bvh));
#endif
#ifdef TRIDENT_HAVE_KDTREE
        case AccelKind::kdtree: return AnyAccel(kind, KdTree::build(mesh, options.kdtree));
#endif
#ifdef TRIDENT_HAVE_OCTREE
        case AccelKind::octree: return AnyAccel(kind, Octree::build(mesh, options.octree));
#endif
        default: break;
    }
    throw std::invalid_argument(fmt::format("--accel {}: not built yet", to_string(kind)));
}

}  // namespace trident
