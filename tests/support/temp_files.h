#pragma once
// Scratch files for tests, in a per-process folder under the system temp directory.
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace trident::testing {

inline std::filesystem::path scratch_dir() {
    const auto dir = std::filesystem::temp_directory_path() / ("trident-tests-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    return dir;
}

inline std::filesystem::path write_file(const std::string& name, const std::string& text) {
    const auto path = scratch_dir() / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

}  // namespace trident::testing
