#include <fmt/format.h>

#include <fstream>
#include <stdexcept>

#include "bench/tables.h"
#include "bench/writers.h"

namespace trident::bench {

void write_markdown(const BenchReport& report, const std::filesystem::path& path) {
    std::string text = "## trident-bench results\n\n";
    for (const std::string& line : report_header_lines(report)) text += fmt::format("- {}\n", line);
    for (const TextTable& table :
         {study_table(report), configurations_table(report), embree_ratio_table(report), paired_ratio_table(report)})
        if (!table.rows.empty()) text += fmt::format("\n{}", render_markdown(table));
    std::ofstream out(path);
    if (!(out << text)) throw std::runtime_error(fmt::format("{}: cannot write the Markdown report", path.string()));
}

}  // namespace trident::bench
