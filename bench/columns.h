#pragma once
// The long-form columns of a configuration row, named once: CSV writes them as its header and
// cells, JSON as each row object's keys, so both always carry the same figures.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <variant>

#include "bench/report.h"

namespace trident::bench {

/// A figure, or nothing where a row has none (Embree has no node count; no reference, no error).
using Cell = std::variant<std::monostate, std::int64_t, double, std::string>;

struct Column {
    std::string_view name;
    Cell (*value)(const BenchRow& row);
};

std::span<const Column> row_columns();

}  // namespace trident::bench
