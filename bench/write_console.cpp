#include <fmt/format.h>

#include "bench/tables.h"
#include "bench/writers.h"

namespace trident::bench {

void print_console(const BenchReport& report, std::FILE* out) {
    fmt::print(out, "trident-bench\n");
    for (const std::string& line : report_header_lines(report)) fmt::print(out, "  {}\n", line);
    for (const TextTable& table :
         {study_table(report), configurations_table(report), embree_ratio_table(report), paired_ratio_table(report)})
        if (!table.rows.empty()) fmt::print(out, "\n{}", render_aligned(table));
}

}  // namespace trident::bench
