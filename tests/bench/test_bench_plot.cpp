// bench/plot.py draws its charts from trident-bench's JSON: the per-structure bars, thread scaling
// and speed against error from a real run, scalar-vs-SIMD and the sweep chart when the JSON has
// several traversals or a sweep (made here from the real run until those land).
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "bench_process.h"

namespace {

using trident::testing::run_command;
using trident::testing::scratch_dir;
namespace fs = std::filesystem;

/// Debian's python3 first: another python3 earlier on PATH may lack matplotlib.
std::optional<std::string> python_with_matplotlib() {
    for (const std::string python : {"/usr/bin/python3", "python3"})
        if (run_command(python + " -c 'import matplotlib' >/dev/null").exit_code == 0) return python;
    return std::nullopt;
}

bool is_png(const fs::path& path) {
    const std::string bytes = trident::testing::read_text(path);
    return bytes.size() > 8 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0;
}

void plot(const std::string& python, const fs::path& json, const fs::path& out) {
    const auto run =
        run_command(python + " " TRIDENT_SOURCE_DIR "/bench/plot.py " + json.string() + " --out " + out.string());
    INFO(run.err);
    REQUIRE(run.exit_code == 0);
}

void write_json(const fs::path& path, const nlohmann::json& json) { std::ofstream(path) << json.dump(); }

}  // namespace

TEST_CASE("plot.py draws the charts its JSON has data for") {
    const auto python = python_with_matplotlib();
    if (!python) {
        MESSAGE("python3-matplotlib is missing: plot.py not tested");
        return;
    }
    const fs::path dir = scratch_dir() / "plot";
    fs::create_directories(dir);
    const auto bench = trident::testing::run_bench(
        "--only teapot --accel brute --width 16 --height 9 --repeats 1 "
        "--threads 1,2 --quiet --json " +
        (dir / "run.json").string());
    INFO(bench.err);
    REQUIRE(bench.exit_code == 0);

    plot(*python, dir / "run.json", dir / "run");
    for (const char* chart : {"build_time.png", "mrays.png", "thread_scaling.png", "speed_vs_error.png"}) {
        CAPTURE(chart);
        CHECK(is_png(dir / "run" / chart));
    }
    CHECK_FALSE(fs::exists(dir / "run" / "scalar_vs_simd.png"));  // one traversal only

    // Several traversals and a sweep in one made-up report (one python start is slow enough).
    const nlohmann::json report = nlohmann::json::parse(trident::testing::read_text(dir / "run.json"));
    nlohmann::json more = report;
    more["sweep"] = {{"name", "octree-depth"}, {"parameter", "max_depth"}};
    for (const auto& row : report.at("rows")) {
        if (row.at("structure") == "embree") continue;
        nlohmann::json packet = row;
        packet["traversal"] = "simd8";
        more["rows"].push_back(packet);
        for (int depth = 1; depth <= 3; ++depth) {
            nlohmann::json swept = row;
            swept["sweep_value"] = depth;
            swept["sweep_parameter"] = "max_depth";
            more["rows"].push_back(swept);
        }
    }
    write_json(dir / "more.json", more);
    plot(*python, dir / "more.json", dir / "more");
    CHECK(is_png(dir / "more" / "scalar_vs_simd.png"));
    CHECK(is_png(dir / "more" / "sweep_octree-depth.png"));
}
