#include "bench/sweep.h"

#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace trident::bench {
namespace {

void set_octree_max_depth(AccelOptions& options, double value) { options.octree.max_depth = int(value); }

/// One bucket count for every node, as the study's BVH (ours bins the largest nodes finer by default).
void set_bvh_bin_count(AccelOptions& options, double value) {
    options.bvh.bin_count = options.bvh.large_node_bin_count = int(value);
}

/// The SAH's traversal cost relative to one triangle test (the study: 1/4).
void set_bvh_cost_ratio(AccelOptions& options, double value) {
    options.bvh.traversal_cost = float(value);
    options.bvh.intersection_cost = 1.0f;
}

/// The KD-tree's triangle-test cost relative to one traversal step (the study: 80).
void set_kdtree_cost_ratio(AccelOptions& options, double value) {
    options.kdtree.traversal_cost = 1.0f;
    options.kdtree.intersection_cost = float(value);
}

void set_kdtree_empty_bonus(AccelOptions& options, double value) { options.kdtree.empty_bonus = float(value); }

/// Levels added to pbrt's depth limit, round(8 + 1.3 log2 N) (the study's).
void set_kdtree_depth_offset(AccelOptions& options, double value) { options.kdtree.depth_offset = int(value); }

/// Havran's perfect splits off (0, the default) or on (1).
void set_kdtree_perfect_splits(AccelOptions& options, double value) { options.kdtree.perfect_splits = value != 0.0; }

}  // namespace

std::span<const SweepSpec> sweep_specs() {
    static const std::vector<SweepSpec> specs = {
        {"octree-depth", AccelKind::octree, "max_depth", {1, 2, 3, 4, 5, 6, 7, 8, 9}, set_octree_max_depth},
        {"bvh-buckets", AccelKind::bvh, "bin_count (every node)", {8, 12, 16, 24, 32, 48, 64}, set_bvh_bin_count},
        {"bvh-cost",
         AccelKind::bvh,
         "traversal_cost/intersection_cost",
         {0.125, 0.25, 0.5, 1, 2, 4},
         set_bvh_cost_ratio},
        {"kd-cost",
         AccelKind::kdtree,
         "intersection_cost/traversal_cost",
         {5, 10, 20, 40, 80, 160},
         set_kdtree_cost_ratio},
        {"kd-empty-bonus",
         AccelKind::kdtree,
         "empty_bonus",
         {0.0, 0.2, 0.4, 0.6, 0.8, 0.9},
         set_kdtree_empty_bonus},
        {"kd-perfect-splits", AccelKind::kdtree, "perfect_splits", {0, 1}, set_kdtree_perfect_splits},
        {"kd-depth",
         AccelKind::kdtree,
         "levels over round(8 + 1.3 log2 N)",
         {-4, -2, 0, 2, 4, 6},
         set_kdtree_depth_offset},
    };
    return specs;
}

const SweepSpec& sweep_or_throw(std::string_view name) {
    std::string known;
    for (const SweepSpec& spec : sweep_specs()) {
        if (spec.name == name) return spec;
        known += known.empty() ? "" : ", ";
        known += spec.name;
    }
    throw std::invalid_argument(fmt::format("--sweep {}: unknown sweep ({})", name, known));
}

}  // namespace trident::bench
