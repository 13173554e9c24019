// trident-bench: builds and traces the acceleration structures side by side on the same rays, as
// the reference study did (build time, render time, Mrays/s), and adds memory, per-ray costs, the
// error against a reference trace, thread and traversal columns, and Embree as a baseline.
// Conventions: ../shared/BENCHMARK.md.
#include <fmt/format.h>

#include <cstdio>
#include <exception>

#include "bench/options.h"
#include "bench/runner.h"
#include "bench/writers.h"

int main(int argc, char** argv) {
    using namespace trident::bench;
    try {
        const auto options = parse_bench_options(argc, argv);
        if (!options) return 0;  // --help
        const BenchReport report = run_benchmark(*options);
        if (report.rows.empty()) {
            fmt::print(stderr, "trident-bench: nothing was measured{}{}\n", report.notes.empty() ? "" : ": ",
                       fmt::join(report.notes, "; "));
            return 1;
        }
        print_console(report, stdout);
        if (options->csv) write_csv(report, *options->csv);
        if (options->json) write_json(report, *options->json);
        if (options->markdown) write_markdown(report, *options->markdown);
        return 0;
    } catch (const std::exception& e) {
        fmt::print(stderr, "trident-bench: {}\n", e.what());
        return 1;
    }
}
