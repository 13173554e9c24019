#include "cli/stress_command.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "stress/stress_cases.h"
#include "stress/stress_runner.h"

namespace trident {

struct StressCommandOptions {
    std::size_t rays = 400'000;
    std::uint64_t seed = 1;
    std::vector<std::string> only;
    std::vector<std::string> accels{"brute", "bvh", "kdtree", "octree"};
    std::vector<std::string> widths{"all"};
    std::string triangle_test = "watertight";
    std::string slabs = "robust";
    int bvh_width = BvhOptions{}.width;
    std::string bvh_builder = "auto";
    std::size_t brute_rays = 20'000;
    int threads = 0;
    std::optional<std::filesystem::path> json;
    bool list = false;
};

namespace {

constexpr std::size_t kMaxRays = 50'000'000;  // per case: about 2 GB of rays, hits and reference

StressRunOptions run_options(const StressCommandOptions& o) {
    StressRunOptions run;
    run.accels.clear();
    for (const std::string& name : o.accels) {
        const auto kind = parse_accel_kind(name);
        if (!kind) throw std::invalid_argument(fmt::format("--accel {}: unknown structure (brute, bvh, bvh2, kdtree, octree)", name));
        run.accels.push_back(*kind);
    }
    run.accel_options.bvh.width = o.bvh_width;
    run.accel_options.bvh.builder = parse_bvh_builder(o.bvh_builder);
    for (const std::string& name : o.widths) {
        if (name == "all") {
            const auto all = runnable_widths();
            run.widths.insert(run.widths.end(), all.begin(), all.end());
            continue;
        }
        const auto width = parse_simd_width(name);
        if (!width) throw std::invalid_argument(fmt::format("--simd {}: expected all or {}", name, kSimdWidthChoices));
        if (!is_runnable(*width)) throw std::invalid_argument(fmt::format("--simd {}: this CPU or build cannot run it", name));
        run.widths.push_back(*width);
    }
    const auto test = parse_triangle_test(o.triangle_test);
    if (!test)
        throw std::invalid_argument(
            fmt::format("--triangle-test {}: expected watertight or moller_trumbore", o.triangle_test));
    run.test = *test;
    const auto slabs = parse_slab_test(o.slabs);
    if (!slabs) throw std::invalid_argument(fmt::format("--slabs {}: expected robust or fast", o.slabs));
    run.slabs = *slabs;
    if (o.rays == 0 || o.rays > kMaxRays)
        throw std::invalid_argument(fmt::format("--rays {}: must lie in 1..{}", o.rays, kMaxRays));
    run.brute_rays = o.brute_rays;
    return run;
}

std::vector<std::string> chosen_cases(const std::vector<std::string>& only) {
    std::vector<std::string> all;
    for (const StressCaseInfo& info : stress_cases()) all.push_back(info.name);
    if (only.empty()) return all;
    for (const std::string& name : only)
        if (std::find(all.begin(), all.end(), name) == all.end())
            throw std::invalid_argument(fmt::format("--only {}: no such case (trident stress --list)", name));
    return only;
}

std::string width_label(SimdWidth width) {
    return width == SimdWidth::scalar ? std::string("scalar") : fmt::format("simd{}", lane_count(width));
}

nlohmann::json to_json(const StressTally& t) {
    return {{"case", t.case_name},
            {"accel", to_string(t.accel)},
            {"simd", width_label(t.width)},
            {"query", to_string(t.query)},
            {"rays", t.rays},
            {"reference_rays", t.reference_rays},
            {"leaks", t.leaks},
            {"hit_miss_disagreements", t.hit_miss_disagreements},
            {"triangle_disagreements", t.triangle_disagreements},
            {"t_beyond_tolerance", t.t_beyond_tolerance},
            {"non_finite", t.non_finite},
            {"max_relative_t_error", t.max_relative_t_error},
            {"mrays_per_s", t.mrays_per_s()}};
}

}  // namespace

StressCommand::StressCommand(CLI::App& app) : options_(std::make_unique<StressCommandOptions>()) {
    command_ = app.add_subcommand("stress", "try to make every structure and width lose a hit or report a wrong one");
    StressCommandOptions& o = *options_;
    command_->add_option("--rays", o.rays, "rays per case (default 400000)");
    command_->add_option("--seed", o.seed, "seed of every case's mesh and rays (default 1)");
    command_->add_option("--only", o.only, "run only these cases (comma-separated; --list names them)")->delimiter(',');
    command_->add_option("--accel", o.accels, "structures, comma-separated (default brute,bvh,bvh2,kdtree,octree)")
        ->delimiter(',');
    command_
        ->add_option("--bvh-width", o.bvh_width,
                     "children per node of the bvh rows' tree: 2, 4, 8 or 16 (default: 16 where AVX2 runs, else 8)")
        ->check(CLI::IsMember({2, 4, 8, 16}));
    command_->add_option("--bvh-builder", o.bvh_builder,
                         "builder of the bvh and bvh2 rows' trees: auto (default: spatial splits where the mesh has "
                         "large triangles and they lower the SAH, binned elsewhere; bvh2 always binned), binned, "
                         "sweep or spatial")
        ->check(CLI::IsMember(bvh_builder_names()));
    command_->add_option("--simd", o.widths, "widths, comma-separated: all (default) or scalar,4,8,16")->delimiter(',');
    command_->add_option("--triangle-test", o.triangle_test, "watertight (default) or moller_trumbore");
    command_->add_option("--slabs", o.slabs, "box tests: robust (default) or fast, to measure what the fast one loses");
    command_->add_option("--brute-rays", o.brute_rays, "rays per case for the brute-force sanity row (default 20000)");
    command_->add_option("--threads", o.threads, "worker threads (0: all cores)")->check(CLI::Range(0, 4096));
    command_->add_option("--json", o.json, "also write every row to this JSON file");
    command_->add_flag("--list", o.list, "list the cases and exit");
}

StressCommand::~StressCommand() = default;

bool StressCommand::parsed() const { return command_->parsed(); }

int StressCommand::run() const {
    const StressCommandOptions& o = *options_;
    if (o.list) {
        for (const StressCaseInfo& info : stress_cases()) fmt::print("  {:<18} {}\n", info.name, info.description);
        return 0;
    }
    const StressRunOptions options = run_options(o);
    const std::vector<std::string> cases = chosen_cases(o.only);
    std::optional<tbb::global_control> parallelism;
    if (o.threads > 0) parallelism.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(o.threads));

    const auto start = std::chrono::steady_clock::now();
    nlohmann::json rows = nlohmann::json::array();
    std::map<std::string, std::size_t> rays_per_config;  // closest-hit rays per structure and width
    std::size_t leaks = 0, disagreements = 0, configs = 0;
    fmt::print("{:<18} {:<7} {:<7} {:<8} {:>9} {:>9} {:>6} {:>8} {:>8} {:>6} {:>6} {:>10} {:>8}\n", "case", "accel", "simd",
               "query", "rays", "checked", "leaks", "hit/miss", "triangle", "t>tol", "nan", "max rel t", "Mrays/s");
    for (const std::string& name : cases) {
        const StressCase stress_case = make_stress_case(name, o.rays, o.seed);
        run_stress_case(stress_case, options, [&](const StressTally& t) {
            fmt::print("{:<18} {:<7} {:<7} {:<8} {:>9} {:>9} {:>6} {:>8} {:>8} {:>6} {:>6} {:>10.2e} {:>8.2f}{}\n",
                       t.case_name, to_string(t.accel), width_label(t.width), to_string(t.query), t.rays,
                       t.reference_rays, t.leaks, t.hit_miss_disagreements, t.triangle_disagreements,
                       t.t_beyond_tolerance, t.non_finite, t.max_relative_t_error, t.mrays_per_s(),
                       t.failures() ? "  FAIL" : "");
            std::fflush(stdout);
            rows.push_back(to_json(t));
            ++configs;
            leaks += t.leaks;
            disagreements += t.failures() - t.leaks;
            if (t.query == StressQuery::closest_hit)
                rays_per_config[fmt::format("{} {}", to_string(t.accel), width_label(t.width))] += t.rays;
        });
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::size_t fewest = SIZE_MAX;
    for (const auto& [config, rays] : rays_per_config)
        if (config.rfind("brute", 0) != 0) fewest = std::min(fewest, rays);
    if (fewest == SIZE_MAX) fewest = 0;
    if (o.json) {
        std::ofstream out(*o.json);
        if (!out) throw std::runtime_error(fmt::format("{}: cannot write", o.json->string()));
        out << nlohmann::json{{"seed", o.seed}, {"rays_per_case", o.rays}, {"triangle_test", o.triangle_test},
                              {"slabs", o.slabs},
                              {"bvh_width", o.bvh_width},
                              {"bvh_builder", o.bvh_builder},
                              {"rows", rows}, {"leaks", leaks}, {"disagreements", disagreements},
                              {"seconds", seconds}}
                   .dump(1)
            << '\n';
        if (!out) throw std::runtime_error(fmt::format("{}: write failed", o.json->string()));
    }
    const bool failed = leaks + disagreements > 0;
    fmt::print("stress: {} ({} cases, {} configurations, {} closest-hit rays and as many any-hit per structure and "
               "width, {} leaks, {} disagreements beyond tolerance, {:.0f} s)\n",
               failed ? "FAIL" : "PASS", cases.size(), configs, fewest, leaks, disagreements, seconds);
    return failed ? 1 : 0;
}

}  // namespace trident
