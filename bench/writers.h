#pragma once
// The report's outputs. Each states the machine, threads, resolution, repeats and reference with
// its figures. The file writers throw std::runtime_error naming the file when it cannot be written.
#include <cstdio>
#include <filesystem>

#include "bench/report.h"

namespace trident::bench {

/// Header lines, the Table 2 layout, every configuration, and the ratios to Embree.
void print_console(const BenchReport& report, std::FILE* out);
/// One header line of column names (bench/columns.h), then one line per configuration.
void write_csv(const BenchReport& report, const std::filesystem::path& path);
/// One object: machine and run settings, then "rows", one object per configuration with every
/// column plus the timing samples.
void write_json(const BenchReport& report, const std::filesystem::path& path);
/// The console's tables as Markdown, ready for bench/RESULTS.md.
void write_markdown(const BenchReport& report, const std::filesystem::path& path);

}  // namespace trident::bench
