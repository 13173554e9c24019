#pragma once
// The stress cases, by name: each generates its mesh and `ray_count` rays from a seed, the same
// ones on every run. What a case is for is in its one-line description.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "stress/stress_case.h"

namespace trident {

struct StressCaseInfo {
    std::string name;
    std::string description;
};

std::vector<StressCaseInfo> stress_cases();
/// Throws std::invalid_argument naming the case when there is no such case.
StressCase make_stress_case(std::string_view name, std::size_t ray_count, std::uint64_t seed);

}  // namespace trident
