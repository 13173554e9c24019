// trident-bench end to end on tiny runs: every output format parses and carries every column,
// a structure compared with itself has exactly zero error, Embree agrees with our brute force.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "bench/embree_baseline.h"
#include "bench/traversal.h"
#include "bench_process.h"
#include "render/hit_buffer.h"
#include "scenes/builtin.h"

namespace {

using trident::testing::BenchRun;
using trident::testing::run_bench;
using trident::testing::run_command;
using trident::testing::scratch_dir;
namespace fs = std::filesystem;

// The long-form columns every CSV header and JSON row must carry (the outputs' contract).
const std::vector<std::string> kColumns = {"scene",
                                           "scene_source",
                                           "triangles",
                                           "load_ms",
                                           "structure",
                                           "traversal",
                                           "rays",
                                           "triangle_test",
                                           "slabs",
                                           "builder",
                                           "threads",
                                           "width",
                                           "height",
                                           "repeats",
                                           "build_ms",
                                           "build_ms_min",
                                           "build_ms_max",
                                           "render_ms",
                                           "render_ms_min",
                                           "render_ms_max",
                                           "mrays_per_s",
                                           "mrays_per_s_min",
                                           "mrays_per_s_max",
                                           "nodes",
                                           "leaves",
                                           "max_depth",
                                           "sah_cost",
                                           "bytes",
                                           "bytes_per_triangle",
                                           "nodes_per_ray",
                                           "triangles_per_ray",
                                           "reference",
                                           "hit_miss_share",
                                           "triangle_share",
                                           "max_relative_t_difference",
                                           "ratio_to_embree",
                                           "speedup_over_one_thread",
                                           "speedup_over_single_rays",
                                           "paired_over_scalar",
                                           "paired_over_bvh",
                                           "paired_over_embree",
                                           "paired_over_embree_best",
                                           "paired_over_closest",
                                           "sweep_parameter",
                                           "sweep_value",
                                           "note"};

// Tiny runs: a 32x18 image of the 6k-triangle teapot, one timed repeat.
const std::string kTiny = "--only teapot --width 32 --height 18 --repeats 1 --quiet ";

std::size_t teapot_triangles() {
    for (const auto& info : trident::builtin_scenes())
        if (info.name == "teapot") return info.triangles;
    FAIL("no built-in teapot");
    return 0;
}

struct Outputs {
    BenchRun run;
    nlohmann::json json;
    std::string csv, markdown;
};

/// One run writing every format, shared by the checks below.
const Outputs& brute_run_with_every_output() {
    static const Outputs outputs = [] {
        const fs::path dir = scratch_dir() / "outputs";
        fs::create_directories(dir);
        Outputs o;
        o.run = run_bench(kTiny + "--accel brute --threads 1,2 --json " + (dir / "r.json").string() + " --csv " +
                          (dir / "r.csv").string() + " --markdown " + (dir / "r.md").string());
        if (o.run.exit_code == 0) {
            o.json = nlohmann::json::parse(trident::testing::read_text(dir / "r.json"));
            o.csv = trident::testing::read_text(dir / "r.csv");
            o.markdown = trident::testing::read_text(dir / "r.md");
        }
        return o;
    }();
    return outputs;
}

std::vector<nlohmann::json> rows_of(const nlohmann::json& json, const std::string& structure) {
    std::vector<nlohmann::json> rows;
    for (const auto& row : json.at("rows"))
        if (row.at("structure") == structure) rows.push_back(row);
    return rows;
}

void check_zero_error(const nlohmann::json& json) {
    REQUIRE_FALSE(json.at("rows").empty());
    for (const auto& row : json.at("rows")) {
        CAPTURE(row.dump());
        REQUIRE(row.at("hit_miss_share").is_number());
        CHECK(row.at("hit_miss_share").get<double>() == 0.0);
        CHECK(row.at("triangle_share").get<double>() == 0.0);
        CHECK(row.at("max_relative_t_difference").get<double>() == 0.0);
    }
}

}  // namespace

TEST_CASE("a run writes JSON with machine info and one row per configuration carrying every column") {
    const Outputs& o = brute_run_with_every_output();
    INFO(o.run.err);
    REQUIRE(o.run.exit_code == 0);
    CHECK(o.run.err.empty());  // --quiet, and stderr is not a terminal anyway
    const nlohmann::json& json = o.json;
    CHECK_FALSE(json.at("machine").at("cpu").get<std::string>().empty());
    CHECK(json.at("machine").at("hardware_threads").get<int>() >= 1);
    CHECK_FALSE(json.at("date").get<std::string>().empty());
    CHECK(json.at("command_line").get<std::string>().find("--accel brute") != std::string::npos);
    CHECK_FALSE(json.at("reference").get<std::string>().empty());
    CHECK(json.at("threads") == nlohmann::json::array({1, 2}));
    CHECK(json.at("repeats") == 1);
    CHECK(json.at("repeats_below_recommended") == true);

    const auto brute = rows_of(json, "brute");
    REQUIRE(brute.size() == 2);  // one per thread count
    CHECK(brute[0].at("threads") == 1);
    CHECK(brute[1].at("threads") == 2);
    for (const auto& row : json.at("rows")) {
        CAPTURE(row.dump());
        for (const std::string& column : kColumns) CHECK_MESSAGE(row.contains(column), column);
        CHECK(row.at("build_ms_min").get<double>() <= row.at("build_ms").get<double>());
        CHECK(row.at("build_ms").get<double>() <= row.at("build_ms_max").get<double>());
        CHECK(row.at("render_ms_min").get<double>() <= row.at("render_ms_max").get<double>());
        CHECK(row.at("render_ms_samples").size() == 1);
        CHECK(row.at("width") == 32);
        CHECK(row.at("height") == 18);
        CHECK(row.at("mrays_per_s").get<double>() ==
              doctest::Approx(32.0 * 18.0 / row.at("render_ms").get<double>() / 1000.0));
        CHECK(row.at("reference") == json.at("reference"));
        CHECK(row.at("speedup_over_one_thread").is_null());  // without --scaling
    }
    for (const auto& row : brute) {
        CHECK(row.at("scene") == "teapot");
        CHECK(row.at("triangles") == teapot_triangles());
        CHECK(row.at("traversal") == "scalar");
        CHECK(row.at("nodes").is_number());
        CHECK(row.at("bytes").get<double>() > 0);
        CHECK(row.at("triangles_per_ray").get<double>() > 0);
    }
}

/// Runs the bench with `options` and checks a paired column of its JSON rows: null where
/// is_paired(row) is false, a positive finite ratio elsewhere. Returns how many rows are paired and
/// the console output.
template <class IsPaired>
std::pair<std::size_t, std::string> paired_rows(const std::string& options, const std::string& column,
                                                IsPaired is_paired) {
    const fs::path json_path = scratch_dir() / (column + ".json");
    const BenchRun run = run_bench(kTiny + options + " --json " + json_path.string());
    INFO(run.err);
    REQUIRE(run.exit_code == 0);
    const auto json = nlohmann::json::parse(trident::testing::read_text(json_path));
    std::size_t paired = 0;
    for (const auto& row : json.at("rows")) {
        CAPTURE(row.dump());
        const auto& ratio = row.at(column);
        if (!is_paired(row)) {
            CHECK(ratio.is_null());  // nothing to pair with
            continue;
        }
        REQUIRE(ratio.is_number());
        CHECK(ratio.get<double>() > 0.0);
        CHECK(std::isfinite(ratio.get<double>()));
        ++paired;
    }
    return {paired, run.out};
}

/// Built without Embree, an option that needs it must be refused with `expected` on stderr; true
/// then (the caller has nothing more to check).
bool refused_without_embree(const std::string& option, const std::string& expected) {
    if (trident::bench::kHaveEmbree) return false;
    const BenchRun run = run_bench(kTiny + option);
    CHECK(run.exit_code != 0);
    CHECK(run.err.find(expected) != std::string::npos);
    MESSAGE("built without Embree: " << option << " is refused");
    return true;
}

TEST_CASE("--scaling times each render of a row at more than one thread again on one thread") {
    const auto [paired, out] =
        paired_rows("--accel bvh --simd scalar --threads 1,2 --scaling", "speedup_over_one_thread",
                    [](const nlohmann::json& row) { return row.at("threads") != 1; });
    CHECK(paired >= 1);  // our BVH at 2 threads, and Embree's rows where it is built
    CHECK(out.find("x 1 thread") != std::string::npos);
}

TEST_CASE("--vs-single times the packet rows of shadow and diffuse rays against single rays in pairs") {
    // Single rays themselves and primary rays have nothing to pair with.
    const auto [paired, out] = paired_rows(
        "--accel kdtree --simd scalar,simd4 --rays primary,shadow,diffuse --threads 1 --embree none --vs-single",
        "speedup_over_single_rays",
        [](const nlohmann::json& row) { return row.at("traversal") != "scalar" && row.at("rays") != "primary"; });
    CHECK(paired == 2);  // shadow and diffuse rays of 4-lane packets
    CHECK(out.find("x single rays") != std::string::npos);
}

TEST_CASE("--paired times each primary row against the same structure's scalar rays and the BVH, run by run") {
    const std::string options =
        "--accel bvh,kdtree,octree --simd scalar,simd4 --threads 1 --embree none --paired scalar,bvh";
    // Packet rows pair with their structure's single rays; the BVH does not pair with itself.
    const auto [over_scalar, out] = paired_rows(
        options, "paired_over_scalar", [](const nlohmann::json& row) { return row.at("traversal") != "scalar"; });
    CHECK(over_scalar == 3);
    CHECK(out.find("Paired speed ratios") != std::string::npos);
    CHECK(out.find("KD x BVH") != std::string::npos);
    [[maybe_unused]] const auto [over_bvh, bvh_out] =
        paired_rows(options, "paired_over_bvh", [](const nlohmann::json& row) { return row.at("structure") != "bvh"; });
    CHECK(over_bvh == 4);  // the KD-tree's and the octree's scalar and 4-lane rows
    [[maybe_unused]] const auto [over_embree, embree_out] =
        paired_rows(options, "paired_over_embree", [](const nlohmann::json&) { return false; });
    CHECK(over_embree == 0);
}

TEST_CASE("--paired embree times each of our primary rows against Embree's call of the same width") {
    if (refused_without_embree("--paired embree", "--paired embree: this binary was built without Embree 3")) return;
    const auto [paired, out] =
        paired_rows("--accel bvh --simd scalar,simd4 --threads 1 --embree 4 --paired embree", "paired_over_embree",
                    [](const nlohmann::json& row) { return row.at("structure") != "embree"; });
    CHECK(paired == 2);
    CHECK(out.find("BVH x Embree") != std::string::npos);
}

TEST_CASE("--paired embree pairs shadow and diffuse rows too, and primary rows with Embree's best") {
    if (!trident::bench::kHaveEmbree) {
        MESSAGE("built without Embree: no Embree partner");
        return;
    }
    const std::string options =
        "--accel bvh,kdtree --simd scalar,simd4 --rays primary,shadow,diffuse --threads 1 --embree none "
        "--paired embree";
    // Every row of ours, of every ray kind, against Embree's call of the same width on the same rays.
    const auto [paired, out] = paired_rows(options, "paired_over_embree", [](const nlohmann::json&) { return true; });
    CHECK(paired == 12);  // 2 structures x 2 traversals x 3 ray kinds
    CHECK(out.find("Paired speed ratios") != std::string::npos);
    // Embree's best (the faster of rtcIntersect16 and its stream) is about primary rays only.
    [[maybe_unused]] const auto [best, best_out] = paired_rows(
        options, "paired_over_embree_best", [](const nlohmann::json& row) { return row.at("rays") == "primary"; });
    CHECK(best == 4);
    CHECK(best_out.find("x Embree best") != std::string::npos);
}

TEST_CASE("--paired closest times each shadow row against the closest hit of the same rays") {
    const auto [paired, out] = paired_rows(
        "--accel bvh,octree --simd scalar,simd4 --rays primary,shadow,diffuse --threads 1 --embree none "
        "--paired closest",
        "paired_over_closest", [](const nlohmann::json& row) { return row.at("rays") == "shadow"; });
    CHECK(paired == 4);  // 2 structures x 2 traversals
    CHECK(out.find("x closest") != std::string::npos);
    for (const char* other : {"paired_over_scalar", "paired_over_bvh", "paired_over_embree"}) {
        CAPTURE(other);
        [[maybe_unused]] const auto [none, none_out] =
            paired_rows("--accel bvh --rays shadow --threads 1 --embree none --paired closest", other,
                        [](const nlohmann::json&) { return false; });
        CHECK(none == 0);
    }
}

TEST_CASE("TRIDENT_ISA caps Embree's rows as it caps ours, unless --embree-isa names another") {
    if (refused_without_embree("--embree 8", "--embree: this binary was built without Embree 3")) return;
    const fs::path json_path = scratch_dir() / "isa_cap.json";
    auto embree_isa = [&](const std::string& environment, const std::string& args) {
        const BenchRun run = run_command(environment + " " + std::string(TRIDENT_BINARY_DIR) + "/trident-bench " + kTiny +
                                         "--accel bvh --simd scalar --threads 1 --embree 8 --json " + json_path.string() +
                                         " " + args);
        INFO(run.err);
        REQUIRE(run.exit_code == 0);
        const auto json = nlohmann::json::parse(trident::testing::read_text(json_path));
        for (const auto& row : rows_of(json, "embree"))
            CHECK(row.at("note").get<std::string>().find(json.at("embree_settings").get<std::string>()) != std::string::npos);
        // Our kernels' cap is in the JSON too: a run set can tell a capped run from a native one.
        const bool capped = environment.rfind("TRIDENT_ISA=", 0) == 0;
        CHECK(json.at("isa_cap").is_null() == !capped);
        if (capped) CHECK(environment.substr(environment.find('=') + 1) == json.at("isa_cap").get<std::string>());
        return json.at("embree_isa").get<std::string>();
    };
    CHECK(embree_isa("env -u TRIDENT_ISA", "") == "native");
    if (__builtin_cpu_supports("avx2")) {
        CHECK(embree_isa("TRIDENT_ISA=avx2", "") == "avx2");
        CHECK(embree_isa("TRIDENT_ISA=avx2", "--embree-isa native") == "native");
    }
    CHECK(embree_isa("TRIDENT_ISA=sse4", "") == "sse4.2");
}

TEST_CASE("--embree stream adds Embree's rtcIntersect1M row on primary rays, as exact as its packets") {
    if (refused_without_embree("--embree stream", "--embree: this binary was built without Embree 3")) return;
    const fs::path json_path = scratch_dir() / "stream.json";
    // 37x21: the image's edge cuts the 8x8 blocks on both sides.
    const BenchRun run = run_bench(
        "--only teapot --width 37 --height 21 --repeats 1 --quiet --accel brute --threads 1 --reference brute "
        "--rays primary,shadow --embree 16,stream --embree-isa avx2 --json " +
        json_path.string());
    INFO(run.err);
    REQUIRE(run.exit_code == 0);
    const auto json = nlohmann::json::parse(trident::testing::read_text(json_path));
    CHECK(json.at("embree_isa") == "avx2");
    CHECK(json.at("embree_settings").get<std::string>().find("max_isa=avx2") != std::string::npos);
    std::vector<std::string> embree_rows;
    for (const auto& row : rows_of(json, "embree")) {
        CAPTURE(row.dump());
        embree_rows.push_back(row.at("rays").get<std::string>() + " " + row.at("traversal").get<std::string>());
        CHECK(row.at("note").get<std::string>().find("max_isa=avx2") != std::string::npos);
        if (row.at("rays") != "primary") continue;
        CHECK(row.at("hit_miss_share").get<double>() < 1e-3);  // against the brute force: the same hits
        CHECK(row.at("triangle_share").get<double>() < 1e-3);
    }
    // The stream row is for primary rays only; shadow rays have their rtcOccluded16 row.
    CHECK(embree_rows ==
          std::vector<std::string>{"primary rtcIntersect16", "primary stream8x8", "shadow rtcOccluded16"});
    CHECK(run.out.find("stream8x8") != std::string::npos);
}

TEST_CASE("the CSV has the column header and as many fields on every row") {
    const Outputs& o = brute_run_with_every_output();
    REQUIRE(o.run.exit_code == 0);
    const auto csv = trident::testing::parse_csv(o.csv);
    REQUIRE(csv.size() == 1 + o.json.at("rows").size());
    CHECK(csv.front() == kColumns);
    for (const auto& row : csv) CHECK(row.size() == kColumns.size());
}

TEST_CASE("the console and Markdown carry the Table 2 layout, the configurations, the CPU and the threads") {
    const Outputs& o = brute_run_with_every_output();
    REQUIRE(o.run.exit_code == 0);
    const std::string cpu = o.json.at("machine").at("cpu");
    for (const std::string* text : {&o.markdown, &o.run.out}) {
        CHECK(text->find(cpu) != std::string::npos);
        CHECK(text->find("threads measured: 1, 2") != std::string::npos);
        CHECK(text->find("fewer than the 5 BENCHMARK.md asks for") != std::string::npos);
        CHECK(text->find(o.json.at("reference").get<std::string>()) != std::string::npos);
    }
    CHECK(o.markdown.find("| scene | triangles | build BVH | build KD | build Octree |") != std::string::npos);
    CHECK(o.markdown.find("| scene | structure | traversal | triangle test | slabs | threads |") != std::string::npos);
    CHECK(o.run.out.find("Table 2") != std::string::npos);
    CHECK(o.run.out.find("Every configuration") != std::string::npos);
}

TEST_CASE("Embree rows trace the same rays and agree with our brute force") {
    const Outputs& o = brute_run_with_every_output();
    REQUIRE(o.run.exit_code == 0);
    if (o.json.at("machine").at("embree_version").is_null()) {
        MESSAGE("built without Embree: no baseline rows to check");
        CHECK(rows_of(o.json, "embree").empty());
        return;
    }
    CHECK(o.json.at("reference").get<std::string>().find("embree rtcIntersect1") != std::string::npos);
    const auto embree = rows_of(o.json, "embree");
    REQUIRE(embree.size() == 10);  // rtcIntersect1/4/8/16 and the stream8x8 at 1 and 2 threads
    for (const auto& row : embree) {
        CAPTURE(row.dump());
        CHECK(row.at("note").get<std::string>().find("RTC_BUILD_QUALITY_HIGH") != std::string::npos);
        CHECK(row.at("bytes").get<double>() > 0);
        CHECK(row.at("nodes").is_null());
        if (row.at("traversal") == "rtcIntersect1") CHECK(row.at("hit_miss_share").get<double>() == 0.0);
        CHECK(row.at("hit_miss_share").get<double>() < 0.01);
        CHECK(row.at("triangle_share").get<double>() < 0.01);
    }
    for (const auto& row : rows_of(o.json, "brute")) {
        CAPTURE(row.dump());
        // An independent tracer on the same rays: triangle indices map one to one.
        CHECK(row.at("hit_miss_share").get<double>() < 0.01);
        CHECK(row.at("triangle_share").get<double>() < 0.01);
        CHECK(row.at("max_relative_t_difference").get<double>() < 1e-3);
        CHECK(row.at("ratio_to_embree").get<double>() > 0.0);
    }
    CHECK(o.run.out.find("Ours / Embree") != std::string::npos);
}

TEST_CASE("--embree-quality builds Embree's rows with the named builder and says so; the reference stays high") {
    auto run_quality = [](const std::string& quality) {
        const fs::path json_path = scratch_dir() / ("embree_quality_" + quality + ".json");
        BenchRun run = run_bench(
            "--only teapot --width 32 --height 18 --repeats 1 --quiet --accel bvh --simd scalar "
            "--threads 1 --embree 1,8 --embree-quality " +
            quality + " --json " + json_path.string());
        return std::pair{
            run, run.exit_code == 0 ? nlohmann::json::parse(trident::testing::read_text(json_path)) : nlohmann::json()};
    };
    const auto [medium_run, medium] = run_quality("medium");
    if (!trident::bench::kHaveEmbree) {
        MESSAGE("built without Embree: --embree-quality is refused");
        CHECK(medium_run.exit_code != 0);
        return;
    }
    INFO(medium_run.err);
    REQUIRE(medium_run.exit_code == 0);
    CHECK(medium.at("embree_settings").get<std::string>().starts_with("RTC_BUILD_QUALITY_MEDIUM"));
    CHECK(medium.at("reference").get<std::string>().find("RTC_BUILD_QUALITY_HIGH") != std::string::npos);
    CHECK(medium_run.out.find("RTC_BUILD_QUALITY_MEDIUM") != std::string::npos);
    const auto rows = rows_of(medium, "embree");
    REQUIRE(rows.size() == 2);
    for (const auto& row : rows) {
        CAPTURE(row.dump());
        CHECK(row.at("note").get<std::string>().starts_with("RTC_BUILD_QUALITY_MEDIUM"));
        CHECK(row.at("build_ms").get<double>() > 0.0);
        // Another tree over the same triangles: the same hits as the high-quality reference.
        CHECK(row.at("hit_miss_share").get<double>() < 0.01);
        CHECK(row.at("triangle_share").get<double>() < 0.01);
    }
    // Another builder ran, not only another label: the trees differ in size.
    const auto [high_run, high] = run_quality("high");
    REQUIRE(high_run.exit_code == 0);
    CHECK(rows_of(high, "embree").at(0).at("note").get<std::string>().starts_with("RTC_BUILD_QUALITY_HIGH"));
    CHECK(rows_of(high, "embree").at(0).at("bytes").get<double>() != rows.at(0).at("bytes").get<double>());
}

TEST_CASE("a structure compared with itself has exactly zero error: --reference self and its own hit buffer") {
    const fs::path dir = scratch_dir() / "self";
    fs::create_directories(dir);
    const std::string run_args = kTiny + "--accel brute --embree none --threads 1 ";

    const BenchRun self = run_bench(run_args + "--reference self --dump-hits " + (dir / "hits").string() + " --json " +
                                    (dir / "self.json").string());
    INFO(self.err);
    REQUIRE(self.exit_code == 0);
    const auto self_json = nlohmann::json::parse(trident::testing::read_text(dir / "self.json"));
    CHECK(self_json.at("reference").get<std::string>().find("self") != std::string::npos);
    check_zero_error(self_json);

    const fs::path dumped = dir / "hits" / "teapot.brute.scalar.hits";
    const trident::HitBuffer hits = trident::read_hit_buffer(dumped);
    CHECK(hits.width == 32);
    CHECK(hits.height == 18);
    CHECK(std::count_if(hits.triangle.begin(), hits.triangle.end(), [](int t) { return t >= 0; }) > 0);

    const BenchRun file =
        run_bench(run_args + "--reference-hits " + dumped.string() + " --json " + (dir / "file.json").string());
    INFO(file.err);
    REQUIRE(file.exit_code == 0);
    const auto file_json = nlohmann::json::parse(trident::testing::read_text(dir / "file.json"));
    CHECK(file_json.at("reference").get<std::string>().find(dumped.string()) != std::string::npos);
    check_zero_error(file_json);

    // A folder of SCENE.hits files serves several scenes.
    fs::create_directories(dir / "folder");
    fs::copy_file(dumped, dir / "folder" / "teapot.hits", fs::copy_options::overwrite_existing);
    const BenchRun folder = run_bench(run_args + "--reference-hits " + (dir / "folder").string() + " --json " +
                                      (dir / "folder.json").string());
    INFO(folder.err);
    REQUIRE(folder.exit_code == 0);
    check_zero_error(nlohmann::json::parse(trident::testing::read_text(dir / "folder.json")));
}

TEST_CASE("--tile-culling off traces every primary ray, with the same hits, and only frustum culling is noted") {
    const fs::path dir = scratch_dir() / "tile_culling";
    fs::create_directories(dir);
    const std::string args =
        "--only teapot --width 160 --height 90 --repeats 1 --quiet --accel bvh,kdtree --simd "
        "scalar,simd4 --threads 1 --embree none --reference self ";
    std::vector<std::string> notes[2];
    for (const bool culling : {true, false}) {
        const std::string name = culling ? "frustum" : "off";
        const BenchRun run = run_bench(args + "--tile-culling " + name + " --dump-hits " + (dir / name).string() +
                                       " --json " + (dir / (name + ".json")).string());
        INFO(run.err);
        REQUIRE(run.exit_code == 0);
        const auto json = nlohmann::json::parse(trident::testing::read_text(dir / (name + ".json")));
        for (const auto& note : json.at("notes")) notes[culling].push_back(note.get<std::string>());
    }
    const auto mentions_culling = [](const std::vector<std::string>& lines) {
        return std::any_of(lines.begin(), lines.end(), [](const std::string& line) {
            return line.find("--tile-culling frustum") != std::string::npos;
        });
    };
    CHECK(mentions_culling(notes[true]));
    CHECK_FALSE(mentions_culling(notes[false]));
    std::size_t compared = 0;
    for (const auto& entry : fs::directory_iterator(dir / "frustum")) {
        CAPTURE(entry.path().filename().string());
        const trident::HitBuffer culled = trident::read_hit_buffer(entry.path());
        const trident::HitBuffer every_ray = trident::read_hit_buffer(dir / "off" / entry.path().filename());
        CHECK(culled.triangle == every_ray.triangle);
        CHECK(culled.t == every_ray.t);
        ++compared;
    }
    CHECK(compared == 4);  // two structures, two traversals
}

TEST_CASE("every runnable packet width gets its own row, traced on the same rays as the scalar one") {
    std::string simd = "scalar";
    for (const char* width : {"simd4", "simd8", "simd16"})
        if (trident::bench::is_runnable(*trident::bench::parse_traversal(width))) simd += std::string(",") + width;
    const fs::path json_path = scratch_dir() / "packets.json";
    const BenchRun run = run_bench(kTiny + "--accel brute --embree none --threads 1 --reference brute --simd " + simd +
                                   " --json " + json_path.string());
    INFO(run.err);
    REQUIRE(run.exit_code == 0);
    const auto json = nlohmann::json::parse(trident::testing::read_text(json_path));
    std::vector<std::string> traversals;
    for (const auto& row : json.at("rows")) {
        CAPTURE(row.dump());
        traversals.push_back(row.at("traversal"));
        // Against the scalar brute force: the packet path must find the same triangles.
        CHECK(row.at("hit_miss_share").get<double>() < 1e-3);
        CHECK(row.at("triangle_share").get<double>() < 1e-3);
        // The brute force tests every triangle once per ray, or once per packet: 2x2, 4x2 or 4x4
        // pixel blocks over the 32x18 image, cut at its bottom edge.
        const std::string traversal = row.at("traversal");
        const int lanes = traversal == "scalar" ? 1 : std::stoi(traversal.substr(4));
        const int block_w = lanes == 1 ? 1 : lanes == 4 ? 2 : 4, block_h = lanes / block_w;
        const double packets = double(((32 + block_w - 1) / block_w) * ((18 + block_h - 1) / block_h));
        CHECK(row.at("triangles_per_ray").get<double>() ==
              doctest::Approx(double(teapot_triangles()) * packets / (32.0 * 18.0)));
    }
    std::string joined;
    for (const std::string& t : traversals) joined += (joined.empty() ? "" : ",") + t;
    CHECK(joined == simd);
}

TEST_CASE("--triangle-test and --slabs lists give one row per variant, each named in its columns") {
    const fs::path json_path = scratch_dir() / "variants.json";
    const BenchRun run = run_bench(kTiny +
                                   "--accel bvh --embree none --threads 1 --reference brute "
                                   "--triangle-test watertight,moller_trumbore --slabs robust,fast --json " +
                                   json_path.string());
    INFO(run.err);
    REQUIRE(run.exit_code == 0);
    const auto json = nlohmann::json::parse(trident::testing::read_text(json_path));
    CHECK(json.at("triangle_test") == "watertight, moller_trumbore");
    CHECK(json.at("slabs") == "robust, fast");
    std::vector<std::string> variants;
    for (const auto& row : json.at("rows")) {
        CAPTURE(row.dump());
        variants.push_back(row.at("triangle_test").get<std::string>() + "/" + row.at("slabs").get<std::string>());
        CHECK(row.at("hit_miss_share").get<double>() < 1e-2);  // the teapot: no variant loses more than an edge
    }
    CHECK(variants == std::vector<std::string>{"watertight/robust", "watertight/fast", "moller_trumbore/robust",
                                               "moller_trumbore/fast"});
    for (const char* bad : {"--slabs exact", "--triangle-test plucker"}) {
        CAPTURE(bad);
        const BenchRun refused = run_bench(kTiny + "--accel bvh " + bad);
        CHECK(refused.exit_code != 0);
    }
}
