// trident-bench --rays: primary, shadow and diffuse rays timed separately, named in the `rays` column.
#include <doctest/doctest.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "bench/embree_baseline.h"
#include "bench_process.h"

namespace fs = std::filesystem;
using trident::testing::BenchRun;
using trident::testing::run_bench;
using trident::testing::scratch_dir;

TEST_CASE("--rays primary,shadow,diffuse gives a row per ray kind for ours and for Embree, each with Mrays/s") {
    const fs::path json_path = scratch_dir() / "rays.json";
    const std::string embree = trident::bench::kHaveEmbree ? "--embree 1,4 " : "--embree none ";
    const BenchRun run = run_bench(
        "--only teapot --width 32 --height 18 --repeats 1 --quiet --accel bvh,kdtree "
        "--threads 1 --simd scalar --rays primary,shadow,diffuse " +
        embree + "--json " + json_path.string());
    INFO(run.err);
    REQUIRE(run.exit_code == 0);
    const auto json = nlohmann::json::parse(trident::testing::read_text(json_path));
    std::map<std::string, int> kinds;
    for (const auto& row : json.at("rows")) {
        CAPTURE(row.dump());
        const std::string kind = row.at("rays");
        ++kinds[row.at("structure").get<std::string>() + " " + kind];
        CHECK(row.at("mrays_per_s").get<double>() > 0.0);
        if (kind != "primary") CHECK(row.at("hit_miss_share").is_null());  // errors are about primary rays
        if (row.at("structure") == "embree" && kind == "shadow")
            CHECK(row.at("traversal").get<std::string>().starts_with("rtcOccluded"));
        if (row.at("structure") == "embree" && kind == "diffuse")
            CHECK(row.at("traversal").get<std::string>().starts_with("rtcIntersect"));
    }
    for (const char* structure : {"bvh", "kdtree"})
        for (const char* kind : {"primary", "shadow", "diffuse"})
            CHECK(kinds[std::string(structure) + " " + kind] == 1);
    if (trident::bench::kHaveEmbree) {
        CHECK(kinds["embree primary"] == 2);
        CHECK(kinds["embree shadow"] == 2);
        CHECK(kinds["embree diffuse"] == 2);  // rtcIntersect1 and rtcIntersect4, as shadow rays
    }
    // The plan's light is stated: the teapot has its own.
    bool light_noted = false;
    for (const auto& note : json.at("notes"))
        light_noted |= note.get<std::string>().find("scene's light") != std::string::npos;
    CHECK(light_noted);
}

TEST_CASE("--rays defaults to primary only, and refuses unknown kinds") {
    const fs::path json_path = scratch_dir() / "rays_default.json";
    const BenchRun run = run_bench(
        "--only teapot --width 16 --height 9 --repeats 1 --quiet --accel bvh --threads 1 "
        "--embree none --json " +
        json_path.string());
    REQUIRE(run.exit_code == 0);
    const auto json = nlohmann::json::parse(trident::testing::read_text(json_path));
    for (const auto& row : json.at("rows")) CHECK(row.at("rays") == "primary");
    const BenchRun refused = run_bench("--only teapot --rays primary,caustic");
    CHECK(refused.exit_code != 0);
    CHECK(refused.err.find("--rays caustic") != std::string::npos);
}
