#include "bench/tables.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>

#include "bench/embree_baseline.h"
#include "bench/traversal.h"
#include "core/intersect_triangle.h"
#include "core/slab_test.h"

namespace trident::bench {
namespace {

constexpr const char* kNone = "-";

/// Three significant digits without an exponent for the figures a table shows.
std::string figure(double value) {
    if (value == 0.0) return "0";
    if (!std::isfinite(value)) return fmt::format("{}", value);
    const double magnitude = std::abs(value);
    if (magnitude >= 1e7 || magnitude < 1e-5) return fmt::format("{:.2e}", value);
    const int decimals = std::max(0, 2 - int(std::floor(std::log10(magnitude))));
    return fmt::format("{:.{}f}", value, decimals);
}

std::string figure(const std::optional<double>& value) { return value ? figure(*value) : kNone; }

/// The study's style: 6.3k, 144k, 1087k.
std::string short_count(std::size_t n) {
    if (n < 1000) return fmt::format("{}", n);
    if (n < 10000) return fmt::format("{:.1f}k", double(n) / 1000.0);
    return fmt::format("{:.0f}k", double(n) / 1000.0);
}

std::string percent(double share) { return share == 0.0 ? "0" : figure(100.0 * share); }

std::optional<double> mebibytes(const BenchRow& row) {
    if (!row.bytes) return std::nullopt;
    return double(*row.bytes) / (1024.0 * 1024.0);
}

std::string range(const Summary& summary) { return fmt::format("{}..{}", figure(summary.min), figure(summary.max)); }

/// A structure's label in the study's table header.
std::string display_name(const std::string& structure) {
    if (structure == "bvh") return "BVH";  // the wide one
    if (structure == "bvh2") return "BVH2";
    if (structure == "kdtree") return "KD";
    if (structure == "octree") return "Octree";
    if (structure == kEmbreeStructure) return "Embree";
    return structure;
}

bool has_structure(const BenchReport& report, const std::string& structure) {
    return std::any_of(report.rows.begin(), report.rows.end(),
                       [&](const BenchRow& r) { return r.structure == structure; });
}

/// The study's three always (a dash where one was left out by --accel), the binary BVH beside the
/// wide one when measured, then brute and Embree if measured.
std::vector<std::string> table_structures(const BenchReport& report, bool with_embree) {
    std::vector<std::string> structures = {"bvh"};
    if (has_structure(report, "bvh2")) structures.push_back("bvh2");
    structures.insert(structures.end(), {"kdtree", "octree"});
    if (has_structure(report, "brute")) structures.push_back("brute");
    if (with_embree && has_structure(report, kEmbreeStructure)) structures.push_back(kEmbreeStructure);
    return structures;
}

struct TableKey {
    std::string scene;
    std::size_t triangles;
    int threads;
    std::string traversal, triangle_test, slabs;
    std::string rays = "primary";  // the ray kind (--rays): shadow and diffuse rows are named so
    bool operator==(const TableKey&) const = default;

    /// The traversal as the tables show it: the variant named when it is not the default.
    std::string traversal_label() const {
        const std::string kind = rays == "primary" ? "" : rays + " ";
        if (triangle_test == to_string(TriangleTest::watertight) && slabs == to_string(SlabTest::robust))
            return kind + traversal;
        return fmt::format("{}{} {} {}", kind, traversal, triangle_test, slabs);
    }
};

std::vector<TableKey> table_keys(const BenchReport& report) {
    std::vector<TableKey> keys;
    for (const BenchRow& row : report.rows) {
        if (row.is_embree()) continue;
        const TableKey key{row.scene,         row.triangles, row.threads, row.traversal,
                           row.triangle_test, row.slabs,     row.ray_kind};
        if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
    }
    return keys;
}

const BenchRow* find_row(const BenchReport& report, const TableKey& key, const std::string& structure) {
    std::string traversal = key.traversal;
    if (structure == kEmbreeStructure) {
        const auto ours = parse_traversal(key.traversal);
        if (!ours) return nullptr;
        traversal = embree_counterpart(*ours, key.rays);
    }
    for (const BenchRow& row : report.rows)
        if (row.scene == key.scene && row.threads == key.threads && row.structure == structure &&
            row.traversal == traversal && row.ray_kind == key.rays &&
            (row.is_embree() || (row.triangle_test == key.triangle_test && row.slabs == key.slabs)))
            return &row;
    return nullptr;
}

using RowFigure = std::function<std::string(const BenchRow&)>;

/// A --paired figure as the tables show it.
struct PairedColumn {
    const char* label;
    std::optional<double> BenchRow::*ratio;
};

/// The --paired figures some row of the report has, in a fixed order.
std::vector<PairedColumn> paired_columns(const BenchReport& report) {
    std::vector<PairedColumn> present;
    for (const PairedColumn& column :
         {PairedColumn{"x scalar", &BenchRow::paired_over_scalar}, PairedColumn{"x BVH", &BenchRow::paired_over_bvh},
          PairedColumn{"x Embree", &BenchRow::paired_over_embree},
          PairedColumn{"x Embree best", &BenchRow::paired_over_embree_best},
          PairedColumn{"x closest", &BenchRow::paired_over_closest}})
        if (std::any_of(report.rows.begin(), report.rows.end(),
                        [&](const BenchRow& r) { return (r.*column.ratio).has_value(); }))
            present.push_back(column);
    return present;
}

constexpr const char* kPairedFootnote =
    "x scalar / x BVH / x Embree / x Embree best / x closest (--paired): each timed render was followed by its "
    "partner's on the same rays (the same structure's scalar traversal; the BVH at the same traversal; Embree's "
    "call of the same width, rtcIntersect1/N or, for shadow rays, rtcOccluded1/N; for primary rays the faster, run "
    "by run, of Embree's rtcIntersect16 and its stream; for shadow rays the same traversal's closest hit); the "
    "median of the pairs' time ratios, partner over row.";

}  // namespace

std::vector<std::string> report_header_lines(const BenchReport& report) {
    const MachineInfo& m = report.machine;
    std::vector<std::string> lines;
    lines.push_back(fmt::format("CPU: {} ({} hardware threads, {} physical cores); threads measured: {}", m.cpu_model,
                                m.hardware_threads, m.physical_cores, fmt::join(report.threads, ", ")));
    std::string repeats = fmt::format(
        "{} primary rays ({}x{}), one per pixel; times are the median of {} run{} after {} "
        "warm-up, min..max kept",
        std::size_t(report.width) * report.height, report.width, report.height, report.repeats,
        report.repeats == 1 ? "" : "s", kWarmupRuns);
    if (report.repeats_below_recommended())
        repeats +=
            fmt::format(" (fewer than the {} BENCHMARK.md asks for: not figures for the record)", kRecommendedRepeats);
    lines.push_back(repeats);
    lines.push_back(fmt::format("triangle test: {}; slab test: {}; error reference: {}", report.triangle_test,
                                report.slabs, report.reference));
    if (!report.embree_settings.empty())
        lines.push_back(fmt::format("Embree {}: {}; device threads = the run's thread count", m.embree_version,
                                    report.embree_settings));
    if (!report.sweep_name.empty())
        lines.push_back(fmt::format("sweep {}: {}", report.sweep_name, report.sweep_parameter));
    lines.push_back(fmt::format("date: {}; compiler: {}", m.date_utc, m.compiler));
    lines.push_back(fmt::format("command: {}", report.command_line));
    for (const std::string& note : report.notes) lines.push_back(fmt::format("note: {}", note));
    return lines;
}

TextTable study_table(const BenchReport& report) {
    TextTable table;
    table.title = "Table 2 layout (build and render in seconds)";
    if (!report.sweep_name.empty()) return table;  // several builds per structure: see the configurations
    const std::vector<std::string> structures = table_structures(report, true);
    const std::vector<std::string> ours = table_structures(report, false);
    table.header = {"scene", "triangles"};
    for (const char* group : {"build", "render", "Mrays/s"})
        for (const std::string& s : structures) table.header.push_back(fmt::format("{} {}", group, display_name(s)));
    table.header.insert(table.header.end(), {"threads", "traversal"});

    struct Group {
        const char* label;
        bool with_embree;
        RowFigure value;
    };
    const std::vector<Group> groups = {
        {"MiB", true, [](const BenchRow& r) { return figure(mebibytes(r)); }},
        {"B/tri", true, [](const BenchRow& r) { return figure(r.bytes_per_triangle()); }},
        {"nodes/ray", false, [](const BenchRow& r) { return figure(r.nodes_per_ray); }},
        {"tris/ray", false, [](const BenchRow& r) { return figure(r.triangles_per_ray); }},
        {"SAH", false, [](const BenchRow& r) { return figure(r.sah_cost); }},
        {"hit/miss %", true, [](const BenchRow& r) { return r.error ? percent(r.error->hit_miss_share) : kNone; }},
        {"tri %", true, [](const BenchRow& r) { return r.error ? percent(r.error->triangle_share) : kNone; }},
    };
    auto names = [](const std::vector<std::string>& list) {
        std::vector<std::string> shown;
        for (const std::string& s : list) shown.push_back(display_name(s));
        return fmt::format("{}", fmt::join(shown, "/"));
    };
    for (const Group& group : groups)
        table.header.push_back(fmt::format("{} {}", group.label, names(group.with_embree ? structures : ours)));

    for (const TableKey& key : table_keys(report)) {
        std::vector<std::string> cells = {key.scene, short_count(key.triangles)};
        auto per_structure = [&](const std::vector<std::string>& list, const RowFigure& value) {
            std::vector<std::string> values;
            for (const std::string& s : list) {
                const BenchRow* row = find_row(report, key, s);
                values.push_back(row ? value(*row) : kNone);
            }
            return values;
        };
        for (const RowFigure& value : {RowFigure([](const BenchRow& r) { return figure(r.build_ms.median / 1000.0); }),
                                       RowFigure([](const BenchRow& r) { return figure(r.render_ms.median / 1000.0); }),
                                       RowFigure([](const BenchRow& r) { return figure(r.mrays_per_s()); })})
            for (std::string& cell : per_structure(structures, value)) cells.push_back(std::move(cell));
        cells.push_back(fmt::format("{}", key.threads));
        cells.push_back(key.traversal_label());
        for (const Group& group : groups)
            cells.push_back(
                fmt::format("{}", fmt::join(per_structure(group.with_embree ? structures : ours, group.value), "/")));
        table.rows.push_back(std::move(cells));
    }
    if (has_structure(report, kEmbreeStructure))
        table.footnotes.push_back(
            "Embree columns: rtcIntersect1 beside scalar rows, rtcIntersectN beside simdN rows; for shadow rows "
            "rtcOccluded1 / rtcOccludedN.");
    table.footnotes.push_back(fmt::format("Errors against {}.", report.reference));
    return table;
}

TextTable configurations_table(const BenchReport& report) {
    TextTable table;
    table.title = "Every configuration (times in ms: median, then min..max)";
    const bool sweep = !report.sweep_name.empty();
    table.header = {"scene", "structure", "traversal", "triangle test", "slabs", "threads", "rays"};
    if (sweep) table.header.insert(table.header.end(), {report.sweep_name, "parameter"});
    table.header.insert(table.header.end(), {"build ms", "build range", "render ms", "render range", "Mrays/s", "nodes",
                                             "leaves", "depth", "SAH", "MiB", "B/tri", "nodes/ray", "tris/ray",
                                             "hit/miss %", "tri %", "max rel dt", "x Embree"});
    const bool scaling = std::any_of(report.rows.begin(), report.rows.end(),
                                     [](const BenchRow& r) { return r.speedup_over_one_thread.has_value(); });
    if (scaling) table.header.push_back("x 1 thread");
    const bool vs_single = std::any_of(report.rows.begin(), report.rows.end(),
                                       [](const BenchRow& r) { return r.speedup_over_single_rays.has_value(); });
    if (vs_single) table.header.push_back("x single rays");
    const std::vector<PairedColumn> paired = paired_columns(report);
    for (const PairedColumn& column : paired) table.header.push_back(fmt::format("{} paired", column.label));
    auto count = [](const std::optional<std::size_t>& n) { return n ? fmt::format("{}", *n) : std::string(kNone); };
    for (const BenchRow& r : report.rows) {
        std::vector<std::string> cells = {r.scene,
                                          r.structure,
                                          r.traversal,
                                          r.triangle_test.empty() ? kNone : r.triangle_test,
                                          r.slabs.empty() ? kNone : r.slabs,
                                          fmt::format("{}", r.threads),
                                          r.ray_kind};
        if (sweep)
            cells.insert(cells.end(), {r.sweep_value ? fmt::format("{:g}", *r.sweep_value) : std::string(kNone),
                                       r.sweep_parameter.empty() ? kNone : r.sweep_parameter});
        cells.insert(
            cells.end(),
            {figure(r.build_ms.median), range(r.build_ms), figure(r.render_ms.median), range(r.render_ms),
             figure(r.mrays_per_s()), count(r.nodes), count(r.leaves), count(r.max_depth), figure(r.sah_cost),
             figure(mebibytes(r)), figure(r.bytes_per_triangle()), figure(r.nodes_per_ray), figure(r.triangles_per_ray),
             r.error ? percent(r.error->hit_miss_share) : kNone, r.error ? percent(r.error->triangle_share) : kNone,
             r.error ? figure(r.error->max_relative_t_difference) : kNone, figure(r.ratio_to_embree)});
        if (scaling) cells.push_back(figure(r.speedup_over_one_thread));
        if (vs_single) cells.push_back(figure(r.speedup_over_single_rays));
        for (const PairedColumn& column : paired) cells.push_back(figure(r.*column.ratio));
        table.rows.push_back(std::move(cells));
    }
    table.footnotes.push_back(
        fmt::format("Errors against {}; max rel dt is the largest relative difference in hit "
                    "distance among rays that both hit.",
                    report.reference));
    if (scaling)
        table.footnotes.push_back(
            "x 1 thread (--scaling): each timed render was run again on one thread right after it; the median "
            "of the pairs' time ratios.");
    if (vs_single)
        table.footnotes.push_back(
            "x single rays (--vs-single): after each timed run of a packet row of shadow or diffuse rays, the same "
            "rays were traced as single rays; the median of the pairs' time ratios.");
    if (!paired.empty()) table.footnotes.push_back(kPairedFootnote);
    return table;
}

TextTable paired_ratio_table(const BenchReport& report) {
    TextTable table;
    table.title = "Paired speed ratios (--paired; above 1 is faster than the partner)";
    const std::vector<PairedColumn> paired = paired_columns(report);
    // One column per structure and partner that some row has.
    struct Column {
        std::string structure;
        const PairedColumn* partner;
    };
    std::vector<Column> columns;
    for (const std::string& s : table_structures(report, false))
        for (const PairedColumn& partner : paired)
            if (std::any_of(report.rows.begin(), report.rows.end(),
                            [&](const BenchRow& r) { return r.structure == s && (r.*partner.ratio).has_value(); }))
                columns.push_back({s, &partner});
    table.header = {"scene", "threads", "traversal"};
    for (const Column& c : columns)
        table.header.push_back(fmt::format("{} {}", display_name(c.structure), c.partner->label));
    for (const TableKey& key : table_keys(report)) {
        std::vector<std::string> cells = {key.scene, fmt::format("{}", key.threads), key.traversal_label()};
        bool any = false;
        for (const Column& c : columns) {
            const BenchRow* row = find_row(report, key, c.structure);
            const std::optional<double> ratio = row ? row->*c.partner->ratio : std::nullopt;
            any = any || ratio.has_value();
            cells.push_back(figure(ratio));
        }
        if (any) table.rows.push_back(std::move(cells));
    }
    if (!table.rows.empty()) table.footnotes.push_back(kPairedFootnote);
    return table;
}

TextTable embree_ratio_table(const BenchReport& report) {
    TextTable table;
    table.title = "Ours / Embree (Mrays/s on the same rays and thread count)";
    const std::vector<std::string> ours = table_structures(report, false);
    table.header = {"scene", "threads", "traversal"};
    for (const std::string& s : ours) table.header.push_back(display_name(s));
    for (const TableKey& key : table_keys(report)) {
        std::vector<std::string> cells = {key.scene, fmt::format("{}", key.threads), key.traversal_label()};
        bool any = false;
        for (const std::string& s : ours) {
            const BenchRow* row = find_row(report, key, s);
            any = any || (row && row->ratio_to_embree);
            cells.push_back(row && row->ratio_to_embree ? figure(*row->ratio_to_embree) : kNone);
        }
        if (any) table.rows.push_back(std::move(cells));
    }
    if (!table.rows.empty())
        table.footnotes.push_back(
            "scalar against rtcIntersect1, simdN against rtcIntersectN (rtcOccluded1/N for shadow rays); above 1 is "
            "faster than Embree.");
    return table;
}

}  // namespace trident::bench
