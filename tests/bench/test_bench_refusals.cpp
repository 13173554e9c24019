// trident-bench refuses what it cannot measure with one clear line on stderr and a non-zero exit:
// bad options, unreadable input, the brute force on big scenes.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "bench/options.h"
#include "bench_process.h"
#include "scenes/builtin.h"
#include "support/sanitizer_workload.h"
#include "support/temp_files.h"

namespace {

using trident::testing::BenchRun;
using trident::testing::run_bench;
using trident::testing::scratch_dir;
namespace fs = std::filesystem;

void check_refused(const BenchRun& run, const std::string& expected) {
    CAPTURE(run.err);
    CHECK(run.exit_code != 0);
    CHECK(trident::testing::count_lines(run.err) == 1);
    CHECK(run.err.rfind("trident-bench: ", 0) == 0);
    CHECK(run.err.find(expected) != std::string::npos);
    CHECK(run.out.empty());
}

/// The smallest built-in scene the brute force must refuse.
std::string big_builtin_scene() {
    std::string name;
    std::size_t smallest = 0;
    for (const auto& info : trident::builtin_scenes())
        if (info.triangles > trident::bench::kBruteMaxTriangles && (name.empty() || info.triangles < smallest))
            name = info.name, smallest = info.triangles;
    REQUIRE_FALSE(name.empty());
    return name;
}

}  // namespace

TEST_CASE("bad options give one line naming the option and a non-zero exit") {
    const auto broken_manifest = trident::testing::write_file("bench_broken.json", "[{\"name\": ");
    const struct {
        std::string args, expected;
    } cases[] = {
        {"--width 0", "--width/--height 0x1080"},
        {"--height 99999", "--width/--height"},
        {"--accel nothing", "--accel nothing: unknown structure"},
        {"--bvh-width 2", "--bvh-width"},  // the binary tree is --accel bvh2
        {"--simd 7", "--simd 7: expected scalar, simd4, simd8 or simd16"},
        {"--repeats 0", "--repeats 0"},
        {"--threads 0", "--threads 0"},
        {"--embree 3", "--embree"},  // "--embree 3: expected ..." or, built without Embree, "--embree: ..."
        {"--embree-quality best", "--embree-quality"},
        {"--last-occluder maybe", "--last-occluder"},
        {"--tile-culling sometimes", "--tile-culling"},
        {"--paired nothing", "--paired nothing: expected scalar, bvh, embree or closest"},
        {"--paired closest", "--paired closest: pairs shadow rows only; add shadow to --rays"},
        {"--paired closest --rays primary,diffuse", "--paired closest: pairs shadow rows only"},
        {"--embree 1,stream,32", "--embree"},   // "--embree 32: expected ..." or, built without Embree, "--embree: ..."
        {"--embree-isa sse3", "--embree-isa"},  // "--embree-isa sse3: expected ..." or "--embree-isa: ... without"
        {"--reference nothing", "--reference nothing"},
        {"--reference-hits /no/such/hits", "/no/such/hits"},
        {"--sweep nothing", "--sweep nothing: unknown sweep"},
        {"--only nothing", "--only nothing: no such scene"},
        {"--frobnicate", "--frobnicate"},
        {"--scenes /no/such/manifest.json", "/no/such/manifest.json"},
        {"--scenes " + broken_manifest.string(), broken_manifest.string()},
        {"--scene /no/such/mesh.obj --accel brute", "/no/such/mesh.obj"},
    };
    for (const auto& c : cases) {
        CAPTURE(c.args);
        check_refused(run_bench(c.args + " --quiet"), c.expected);
    }
}

TEST_CASE("an Embree ISA this CPU does not run is refused as such") {
    if (!trident::bench::kHaveEmbree) return;
    for (trident::bench::EmbreeIsa isa : trident::bench::kAllEmbreeIsas) {
        const std::string name = trident::bench::to_string(isa);
        CAPTURE(name);
        if (!trident::bench::cpu_runs(isa))
            check_refused(run_bench("--embree-isa " + name), "--embree-isa " + name + ": this CPU does not run it");
        else  // Embree takes the limit in its device config and traces with it
            CHECK(run_bench("--only teapot --accel bvh --width 8 --height 8 --repeats 1 --threads 1 --quiet "
                            "--embree 1 --embree-isa " +
                            name)
                      .exit_code == 0);
    }
}

TEST_CASE("packet widths this CPU cannot run are refused as such") {
    for (const std::string simd : {"simd4", "simd8", "simd16", "4", "8", "16"})
        if (!trident::bench::is_runnable(*trident::bench::parse_traversal(simd)))
            check_refused(run_bench("--simd " + simd), "--simd " + simd + ": not runnable here");
}

TEST_CASE("a reference hit buffer of another size is refused") {
    const fs::path dir = scratch_dir() / "wrong_size";
    const BenchRun dump = run_bench(
        "--only teapot --accel brute --embree none --reference self --width 8 --height 8 "
        "--repeats 1 --threads 1 --quiet --dump-hits " +
        dir.string());
    REQUIRE(dump.exit_code == 0);
    check_refused(run_bench("--only teapot --accel brute --embree none --width 16 --height 8 --repeats 1 --quiet "
                            "--reference-hits " +
                            (dir / "teapot.brute.scalar.hits").string()),
                  "8x8 rays, but this run traces 16x8");
}

TEST_CASE("the brute force is refused above 100k triangles, named in the notes, or as the one error") {
    const std::string big = big_builtin_scene();
    const std::string args =
        "--accel brute --embree none --reference self --width 8 --height 8 --repeats 1 --threads 1 --quiet ";

    check_refused(run_bench(args + "--only " + big), "brute refused on " + big);

    const fs::path json_path = scratch_dir() / "refusal.json";
    const BenchRun mixed = run_bench(args + "--only teapot," + big + " --json " + json_path.string());
    INFO(mixed.err);
    REQUIRE(mixed.exit_code == 0);
    const auto json = nlohmann::json::parse(trident::testing::read_text(json_path));
    for (const auto& row : json.at("rows")) CHECK(row.at("scene") == "teapot");
    REQUIRE(json.at("notes").size() == 1);
    CHECK(json.at("notes")[0].get<std::string>().find("brute refused on " + big) != std::string::npos);
    CHECK(mixed.out.find("brute refused on " + big) != std::string::npos);
}

/// A rippled 20x20 grid of quads, 800 triangles, as an OBJ in the scratch folder.
fs::path write_rippled_grid() {
    constexpr int kQuads = 20;
    std::string text;
    for (int z = 0; z <= kQuads; ++z)
        for (int x = 0; x <= kQuads; ++x)
            text += fmt::format("v {} {:.5f} {}\n", x, 0.8 * std::sin(0.7 * x) * std::cos(0.5 * z), z);
    for (int z = 0; z < kQuads; ++z)
        for (int x = 0; x < kQuads; ++x) {
            const int a = z * (kQuads + 1) + x + 1, b = a + 1, c = a + kQuads + 1, d = c + 1;
            text += fmt::format("f {} {} {}\nf {} {} {}\n", a, c, b, b, c, d);
        }
    return trident::testing::write_file("rippled_grid.obj", text);
}

TEST_CASE("each sweep runs its structure over every value") {
    // The sanitizer run sweeps a grid of 800 triangles, not the teapot's 6,320: its seven sweeps
    // of sanitized builds took 12 s of that run (bench/experiments/test_time.md).
    const std::string scene =
        trident::testing::kSanitized ? "--scene " + write_rippled_grid().string() : std::string("--only teapot");
    for (const std::string name :
         {"octree-depth", "bvh-buckets", "bvh-cost", "kd-cost", "kd-empty-bonus", "kd-perfect-splits", "kd-depth"}) {
        CAPTURE(name);
        const fs::path json_path = scratch_dir() / ("sweep_" + name + ".json");
        const BenchRun run = run_bench("--sweep " + name + " " + scene +
                                       " --embree none --reference self --width 8 "
                                       "--height 8 --repeats 1 --threads 1 --quiet --json " +
                                       json_path.string());
        INFO(run.err);
        REQUIRE(run.exit_code == 0);
        const auto json = nlohmann::json::parse(trident::testing::read_text(json_path));
        CHECK(json.at("sweep").at("name") == name);
        REQUIRE(json.at("rows").size() >= 2);  // every sweep has two values at least (perfect splits: off, on)
        std::set<double> values;
        for (const auto& row : json.at("rows")) {
            CHECK(row.at("structure") == json.at("rows")[0].at("structure"));
            CHECK_FALSE(row.at("sweep_parameter").get<std::string>().empty());
            values.insert(row.at("sweep_value").get<double>());
        }
        CHECK(values.size() == json.at("rows").size());
        CHECK(run.out.find(name) != std::string::npos);
    }
}
