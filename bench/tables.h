#pragma once
// The report as tables, for the console and for Markdown alike.
#include <string>
#include <vector>

#include "bench/report.h"
#include "bench/text_table.h"

namespace trident::bench {

/// What must stand above any figure: CPU, threads, resolution, repeats (and a warning below
/// BENCHMARK.md's 5), triangle test, reference, Embree's settings, date, command line, notes.
std::vector<std::string> report_header_lines(const BenchReport& report);

/// The reference study's Table 2: one row per scene, thread count and traversal; its columns
/// first (triangles, then build and render in seconds and Mrays/s per structure, Embree beside
/// them when measured), ours after (threads, traversal, then memory, bytes per triangle, nodes
/// and triangles per ray, SAH cost and the error shares, one "a/b/c" cell per figure). No rows
/// in a sweep, where the configurations table says it all.
TextTable study_table(const BenchReport& report);

/// One row per configuration with every figure, the swept parameter first in a sweep.
TextTable configurations_table(const BenchReport& report);

/// --paired: per scene, threads and traversal, each structure's median paired ratio over each
/// partner; no rows without --paired.
TextTable paired_ratio_table(const BenchReport& report);

/// Our Mrays/s over Embree's on the same rays and threads; no rows without Embree.
TextTable embree_ratio_table(const BenchReport& report);

}  // namespace trident::bench
