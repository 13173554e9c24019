#include <fmt/format.h>

#include <fstream>
#include <stdexcept>

#include "bench/columns.h"
#include "bench/writers.h"

namespace trident::bench {
namespace {

/// RFC 4180: a field with a comma, quote or line break is quoted, its quotes doubled.
std::string csv_field(const std::string& text) {
    if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
    std::string quoted = "\"";
    for (char c : text) {
        if (c == '"') quoted += '"';
        quoted += c;
    }
    quoted += '"';
    return quoted;
}

std::string csv_cell(const Cell& cell) {
    struct {
        std::string operator()(std::monostate) const { return {}; }
        std::string operator()(std::int64_t v) const { return fmt::format("{}", v); }
        std::string operator()(double v) const { return fmt::format("{}", v); }  // shortest exact form
        std::string operator()(const std::string& v) const { return csv_field(v); }
    } format;
    return std::visit(format, cell);
}

}  // namespace

void write_csv(const BenchReport& report, const std::filesystem::path& path) {
    const auto columns = row_columns();
    std::string text;
    for (std::size_t c = 0; c < columns.size(); ++c) {
        if (c) text += ',';
        text += columns[c].name;
    }
    text += "\n";
    for (const BenchRow& row : report.rows) {
        for (std::size_t c = 0; c < columns.size(); ++c) {
            if (c) text += ',';
            text += csv_cell(columns[c].value(row));
        }
        text += "\n";
    }
    std::ofstream out(path);
    if (!(out << text)) throw std::runtime_error(fmt::format("{}: cannot write the CSV file", path.string()));
}

}  // namespace trident::bench
