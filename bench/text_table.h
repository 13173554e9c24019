#pragma once
// A table of already formatted cells, rendered either aligned for the console or as a Markdown
// pipe table; the report's tables are built once and written both ways.
#include <string>
#include <vector>

namespace trident::bench {

struct TextTable {
    std::string title;
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;  // each as long as the header
    std::vector<std::string> footnotes;          // lines printed under the table
};

/// Columns padded to their widest cell; text columns left-aligned, figures right-aligned.
std::string render_aligned(const TextTable& table);
/// "| a | b |" rows under a "| --- |" rule, title as a "###" heading, footnotes as a paragraph.
std::string render_markdown(const TextTable& table);

}  // namespace trident::bench
