#pragma once
// One value holding whichever structure a run chose, so the renderer and the benchmark are
// written once: `accel.visit([&](const auto& structure) { ... })` hands over the concrete type
// and every traversal inlines into the caller's loop.
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "accel/brute/brute_force.h"
#include "core/mesh.h"

namespace trident {

enum class AccelKind { brute, bvh, kdtree, octree };

const char* to_string(AccelKind kind);
std::optional<AccelKind> parse_accel_kind(std::string_view name);
/// Whether this binary contains the structure (all do once their issues have landed).
bool is_built(AccelKind kind);
std::vector<AccelKind> built_accel_kinds();

struct AccelOptions {};

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
    using Structure = std::variant<BruteForce>;
    AnyAccel(AccelKind kind, Structure structure) : kind_(kind), structure_(std::move(structure)) {}
    AccelKind kind_;
    Structure structure_;
};

}  // namespace trident
