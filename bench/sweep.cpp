#include "bench/sweep.h"

#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace trident::bench {

std::span<const SweepSpec> sweep_specs() {
    using namespace sweep_setters;
    static const std::vector<SweepSpec> specs = {
        {"octree-depth", AccelKind::octree, "max_depth", {1, 2, 3, 4, 5, 6, 7, 8, 9}, octree_max_depth()},
        {"bvh-buckets", AccelKind::bvh, "bin_count (every node)", {8, 12, 16, 24, 32, 48, 64}, bvh_bin_count()},
        {"bvh-cost", AccelKind::bvh, "traversal_cost/intersection_cost", {0.125, 0.25, 0.5, 1, 2, 4}, bvh_cost_ratio()},
        {"kd-cost",
         AccelKind::kdtree,
         "intersection_cost/traversal_cost",
         {5, 10, 20, 40, 80, 160},
         kdtree_cost_ratio()},
        {"kd-empty-bonus", AccelKind::kdtree, "empty_bonus", {0.0, 0.2, 0.4, 0.6, 0.8, 0.9}, kdtree_empty_bonus()},
    };
    return specs;
}

const SweepSpec& sweep_or_throw(std::string_view name) {
    std::string known;
    for (const SweepSpec& spec : sweep_specs()) {
        if (spec.name == name) {
            if (spec.set == nullptr)
                throw std::invalid_argument(fmt::format("--sweep {}: not built yet ({} {} is not in this binary)", name,
                                                        to_string(spec.structure), spec.parameter));
            return spec;
        }
        known += known.empty() ? "" : ", ";
        known += spec.name;
    }
    throw std::invalid_argument(fmt::format("--sweep {}: unknown sweep ({})", name, known));
}

}  // namespace trident::bench
