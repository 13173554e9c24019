#include "bench/text_table.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

namespace trident::bench {
namespace {

bool looks_numeric(const std::string& cell) {
    return !cell.empty() && (std::isdigit(static_cast<unsigned char>(cell.front())) || cell == "-" ||
                             (cell.size() > 1 && (cell.front() == '-' || cell.front() == '~')));
}

std::string escape_markdown(const std::string& cell) {
    std::string escaped;
    for (char c : cell) {
        if (c == '|') escaped += '\\';
        escaped += c;
    }
    return escaped;
}

}  // namespace

std::string render_aligned(const TextTable& table) {
    std::vector<std::size_t> widths(table.header.size(), 0);
    std::vector<bool> numeric(table.header.size(), true);
    for (std::size_t c = 0; c < table.header.size(); ++c) widths[c] = table.header[c].size();
    for (const auto& row : table.rows)
        for (std::size_t c = 0; c < row.size() && c < widths.size(); ++c) {
            widths[c] = std::max(widths[c], row[c].size());
            numeric[c] = numeric[c] && looks_numeric(row[c]);
        }
    auto line = [&](const std::vector<std::string>& cells) {
        std::string out;
        for (std::size_t c = 0; c < cells.size(); ++c) {
            if (c) out += "  ";
            out += numeric[c] ? fmt::format("{:>{}}", cells[c], widths[c]) : fmt::format("{:<{}}", cells[c], widths[c]);
        }
        while (!out.empty() && out.back() == ' ') out.pop_back();
        return out + "\n";
    };
    std::string out = table.title.empty() ? std::string() : fmt::format("{}\n", table.title);
    out += line(table.header);
    std::size_t rule = 0;
    for (std::size_t w : widths) rule += w + 2;
    out += std::string(rule > 2 ? rule - 2 : 0, '-') + "\n";
    for (const auto& row : table.rows) out += line(row);
    for (const std::string& note : table.footnotes) out += fmt::format("{}\n", note);
    return out;
}

std::string render_markdown(const TextTable& table) {
    std::string out = table.title.empty() ? std::string() : fmt::format("### {}\n\n", table.title);
    auto line = [](const std::vector<std::string>& cells) {
        std::string out = "|";
        for (const std::string& cell : cells) out += fmt::format(" {} |", escape_markdown(cell));
        return out + "\n";
    };
    out += line(table.header);
    out += line(std::vector<std::string>(table.header.size(), "---"));
    for (const auto& row : table.rows) out += line(row);
    for (const std::string& note : table.footnotes) out += fmt::format("\n{}\n", note);
    return out;
}

}  // namespace trident::bench
