#include <doctest/doctest.h>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include "render/hit_buffer.h"
#include "render/image.h"
#include "support/temp_files.h"

namespace {

struct Run {
    int exit_code;
    std::string output;  // stdout and stderr
};

/// `environment`: assignments put before the command, e.g. "TRIDENT_ISA=avx2".
Run run_trident(const std::string& args, const std::string& environment = "") {
    const std::string command =
        (environment.empty() ? "" : environment + " ") + std::string(TRIDENT_BINARY_DIR) + "/trident " + args + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    REQUIRE(pipe != nullptr);
    std::string output;
    std::array<char, 4096> buffer{};
    while (std::fgets(buffer.data(), int(buffer.size()), pipe)) output += buffer.data();
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

std::size_t lines(const std::string& text) {
    std::size_t n = 0;
    for (char c : text) n += c == '\n';
    return n;
}

}  // namespace

TEST_CASE("bad options and bad input give one line and a non-zero exit") {
    const auto bad_obj = trident::testing::write_file("cli_bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    for (const std::string& args : std::vector<std::string>{
             "render teapot --width 0", "render teapot --height 99999", "render teapot --accel nothing",
          "render teapot --mode sepia", "render teapot --simd 7", "render teapot --frobnicate",
          "render /no/such/file.obj", "render " + bad_obj.string(), "render no_such_scene",
          "info teapot --scenes /no/such/manifest.json", "render teapot --threads -1",
          "render teapot --mode ao --ao-samples 0", "render teapot --mode heat --heat leaves",
          "render teapot --slabs loose", "stress --slabs loose", "stress --triangle-test exact",
          "stress --only no_such_case", "stress --rays 0", "stress --simd 3",
          "info teapot --accel octree --octree-overlap sphere", "info teapot --bvh-builder greedy",
          "info teapot --accel kdtree --kd-depth-offset 64", "info teapot --bvh-width 3", "stress --bvh-width 32"}) {
        CAPTURE(args);
        const Run run = run_trident(args);
        CHECK(run.exit_code != 0);
        CHECK(lines(run.output) == 1);
        CHECK(run.output.rfind("trident: ", 0) == 0);
    }
}

TEST_CASE("render writes a PNG and a hit buffer of the requested size") {
    const auto dir = trident::testing::scratch_dir();
    const Run run = run_trident("render teapot --accel brute --width 64 --height 36 --output " + (dir / "t.png").string() +
                                " --dump-hits " + (dir / "t.hits").string());
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    const trident::Image image = trident::read_png(dir / "t.png");
    CHECK(image.width == 64);
    CHECK(image.height == 36);
    const trident::HitBuffer hits = trident::read_hit_buffer(dir / "t.hits");
    CHECK(hits.width == 64);
    std::size_t hit_count = 0;
    for (auto t : hits.triangle) hit_count += t >= 0;
    CHECK(hit_count > 64 * 36 / 10);  // the teapot fills a good part of its own camera's view
    CHECK(hit_count < 64 * 36);
}

TEST_CASE("info --kd-depth-offset moves the KD-tree's depth limit") {
    // Teapot: 6320 triangles, limit round(8 + 1.3 log2 6320) = 24, which its tree reaches.
    auto depth = [](const std::string& extra) {
        const Run run = run_trident("info teapot --accel kdtree" + extra);
        REQUIRE(run.exit_code == 0);
        const std::size_t at = run.output.find(", depth ");
        REQUIRE(at != std::string::npos);
        return std::stoi(run.output.substr(at + 8));
    };
    CHECK(depth("") == 24);
    CHECK(depth(" --kd-depth-offset -10") == 14);
}

TEST_CASE("cpu names the CPU and the kernels; TRIDENT_ISA caps them, and a bad cap is one line and an error") {
    const Run run = run_trident("cpu");
    CHECK(run.exit_code == 0);
    CHECK(run.output.find("cpu:") != std::string::npos);
    CHECK(run.output.find("--simd auto:") != std::string::npos);
    const Run capped = run_trident("cpu", "TRIDENT_ISA=sse4");
    CHECK(capped.exit_code == 0);
    CHECK(capped.output.find("--simd auto: 4") != std::string::npos);
    for (const std::string& args : {std::string("cpu"), std::string("render teapot --simd auto --output /dev/null")}) {
        CAPTURE(args);
        const Run bad = run_trident(args, "TRIDENT_ISA=avx9");
        CHECK(bad.exit_code != 0);
        CHECK(lines(bad.output) == 1);
        CHECK(bad.output.find("TRIDENT_ISA=avx9") != std::string::npos);
    }
    const Run too_wide = run_trident("render teapot --simd 8 --width 16 --height 16 --output /dev/null", "TRIDENT_ISA=sse4");
    CHECK(too_wide.exit_code != 0);
    CHECK(lines(too_wide.output) == 1);
    CHECK(too_wide.output.rfind("trident: --simd 8: ", 0) == 0);
}

TEST_CASE("scenes lists the built-in scenes") {
    const Run run = run_trident("scenes");
    CHECK(run.exit_code == 0);
    CHECK(run.output.find("teapot") != std::string::npos);
}

TEST_CASE("render --explain prints the plan, one line per pass, and writes nothing") {
    const auto dir = trident::testing::scratch_dir();
    const auto png = dir / "explain.png";
    const Run lit = run_trident("render teapot --explain --output " + png.string());
    INFO(lit.output);
    REQUIRE(lit.exit_code == 0);
    CHECK(lines(lit.output) == 6);  // the title and five passes
    CHECK(lit.output.find("shadow: any-hit") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(png));
    const auto obj = trident::testing::write_file("explain_dark.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const Run dark = run_trident("render " + obj.string() + " --explain");
    CHECK(dark.exit_code == 0);
    CHECK(dark.output.find("shadow: skipped (the scene has no light") != std::string::npos);
    CHECK(dark.output.find("normals: geometric") != std::string::npos);
}

TEST_CASE("render --mode ao and --mode heat write images of the requested size") {
    const auto dir = trident::testing::scratch_dir();
    for (const std::string& mode : {std::string("ao --ao-samples 3"), std::string("heat --heat triangles --simd 4"),
                                    std::string("heat --simd scalar")}) {
        CAPTURE(mode);
        const Run run = run_trident("render teapot --width 80 --height 50 --mode " + mode + " --output " +
                                    (dir / "m.png").string());
        INFO(run.output);
        REQUIRE(run.exit_code == 0);
        const trident::Image image = trident::read_png(dir / "m.png");
        CHECK(image.width == 80);
        CHECK(image.height == 50);
    }
}
