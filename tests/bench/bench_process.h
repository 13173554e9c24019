#pragma once
// Runs the built trident-bench binary as a user would, keeping its exit code, stdout and stderr
// apart (errors must be one line on stderr), and small readers for what it writes.
#include <doctest/doctest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/temp_files.h"

namespace trident::testing {

struct BenchRun {
    int exit_code = -1;
    std::string out, err;
};

inline std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

inline BenchRun run_command(const std::string& command) {
    const auto err_path = scratch_dir() / "bench_stderr.txt";
    FILE* pipe = popen((command + " 2>" + err_path.string()).c_str(), "r");
    REQUIRE(pipe != nullptr);
    BenchRun run;
    std::array<char, 4096> buffer{};
    while (std::fgets(buffer.data(), int(buffer.size()), pipe)) run.out += buffer.data();
    const int status = pclose(pipe);
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.err = read_text(err_path);
    return run;
}

inline BenchRun run_bench(const std::string& args) {
    return run_command(std::string(TRIDENT_BINARY_DIR) + "/trident-bench " + args);
}

inline std::size_t count_lines(const std::string& text) {
    std::size_t n = 0;
    for (char c : text) n += c == '\n';
    return n;
}

/// RFC 4180 fields of each line (quoted fields may hold commas and doubled quotes).
inline std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
    std::vector<std::vector<std::string>> rows;
    std::vector<std::string> row;
    std::string field;
    bool quoted = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (quoted) {
            if (c == '"' && i + 1 < text.size() && text[i + 1] == '"')
                field += '"', ++i;
            else if (c == '"')
                quoted = false;
            else
                field += c;
        } else if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            row.push_back(field), field.clear();
        } else if (c == '\n') {
            row.push_back(field), field.clear();
            rows.push_back(row), row.clear();
        } else {
            field += c;
        }
    }
    return rows;
}

}  // namespace trident::testing
