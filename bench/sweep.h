#pragma once
// Parameter sweeps: one structure built over a range of one build option, everything else as in a
// normal run (the reference study's Figure 16 sweeps the octree depth). A sweep pairs the
// structure with a setter that writes the value into AccelOptions.
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
    SweepSetter set;
};

/// Every sweep trident-bench knows.
std::span<const SweepSpec> sweep_specs();

/// Throws std::invalid_argument with one line naming the known sweeps when `name` is not one.
const SweepSpec& sweep_or_throw(std::string_view name);

}  // namespace trident::bench
