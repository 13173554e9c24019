#pragma once
// Parameter sweeps: one structure built over a range of one build option, everything else as in a
// normal run (the reference study's Figure 16 sweeps the octree depth). A sweep pairs the
// structure with a setter that writes the value into AccelOptions.
//
// Each setter is written against the option field the structure's builder reads
// (`AccelOptions::octree.max_depth`, `bvh.bin_count`, `bvh.traversal_cost`, ...). Until
// AccelOptions carries that field the setter is null and the sweep is refused with "not built
// yet", so this file compiles unchanged before and after a structure lands.
#include <span>
#include <string_view>
#include <vector>

#include "accel/any_accel.h"

namespace trident::bench {

using SweepSetter = void (*)(AccelOptions&, double value);

struct SweepSpec {
    std::string_view name;  // the --sweep argument
    AccelKind structure;
    std::string_view parameter;  // what the value means, for tables and charts
    std::vector<double> values;
    SweepSetter set = nullptr;  // null while AccelOptions lacks the field
};

namespace sweep_setters {

// Templates only so that the requires-expressions are checked when AccelOptions is complete and
// may or may not have the field; O is always AccelOptions.
template <class O = AccelOptions>
constexpr SweepSetter octree_max_depth() {
    if constexpr (requires(O o) { o.octree.max_depth = 1; })
        return [](O& o, double value) { o.octree.max_depth = int(value); };
    else
        return nullptr;
}

/// One bucket count for every node, as the study's BVH (ours bins the largest nodes finer by default).
template <class O = AccelOptions>
constexpr SweepSetter bvh_bin_count() {
    if constexpr (requires(O o) {
                      o.bvh.bin_count = 1;
                      o.bvh.large_node_bin_count = 1;
                  })
        return [](O& o, double value) { o.bvh.bin_count = o.bvh.large_node_bin_count = int(value); };
    else
        return nullptr;
}

/// The SAH's traversal cost relative to one triangle test (the study: 1/4).
template <class O = AccelOptions>
constexpr SweepSetter bvh_cost_ratio() {
    if constexpr (requires(O o) {
                      o.bvh.traversal_cost = 1.0f;
                      o.bvh.intersection_cost = 1.0f;
                  })
        return [](O& o, double value) {
            o.bvh.traversal_cost = float(value);
            o.bvh.intersection_cost = 1.0f;
        };
    else
        return nullptr;
}

/// The KD-tree's triangle-test cost relative to one traversal step (the study: 80).
template <class O = AccelOptions>
constexpr SweepSetter kdtree_cost_ratio() {
    if constexpr (requires(O o) {
                      o.kdtree.traversal_cost = 1.0f;
                      o.kdtree.intersection_cost = 1.0f;
                  })
        return [](O& o, double value) {
            o.kdtree.traversal_cost = 1.0f;
            o.kdtree.intersection_cost = float(value);
        };
    else
        return nullptr;
}

template <class O = AccelOptions>
constexpr SweepSetter kdtree_empty_bonus() {
    if constexpr (requires(O o) { o.kdtree.empty_bonus = 0.5f; })
        return [](O& o, double value) { o.kdtree.empty_bonus = float(value); };
    else
        return nullptr;
}

}  // namespace sweep_setters

/// Every sweep trident-bench knows, built or not.
std::span<const SweepSpec> sweep_specs();

/// Throws std::invalid_argument with one line: unknown name (listing the known ones), or
/// "not built yet" when the structure or its option field is missing from this binary.
const SweepSpec& sweep_or_throw(std::string_view name);

}  // namespace trident::bench
