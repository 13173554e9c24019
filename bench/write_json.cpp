#include <fmt/format.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "bench/columns.h"
#include "bench/writers.h"

namespace trident::bench {
namespace {

nlohmann::json json_cell(const Cell& cell) {
    struct {
        nlohmann::json operator()(std::monostate) const { return nullptr; }
        nlohmann::json operator()(std::int64_t v) const { return v; }
        // JSON has no infinities or NaN: they become null rather than an unreadable file.
        nlohmann::json operator()(double v) const {
            return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
        }
        nlohmann::json operator()(const std::string& v) const { return v; }
    } convert;
    return std::visit(convert, cell);
}

nlohmann::json json_row(const BenchRow& row) {
    nlohmann::json object = nlohmann::json::object();
    for (const Column& column : row_columns()) object[std::string(column.name)] = json_cell(column.value(row));
    object["build_ms_samples"] = row.build_ms.samples;
    object["render_ms_samples"] = row.render_ms.samples;
    return object;
}

}  // namespace

void write_json(const BenchReport& report, const std::filesystem::path& path) {
    const MachineInfo& m = report.machine;
    nlohmann::json json = {
        {"tool", "trident-bench"},
        {"machine",
         {{"cpu", m.cpu_model},
          {"hardware_threads", m.hardware_threads},
          {"physical_cores", m.physical_cores},
          {"compiler", m.compiler},
          {"embree_version", m.embree_version.empty() ? nlohmann::json(nullptr) : nlohmann::json(m.embree_version)}}},
        {"date", m.date_utc},
        {"command_line", report.command_line},
        {"width", report.width},
        {"height", report.height},
        {"repeats", report.repeats},
        {"warmup_runs", kWarmupRuns},
        {"repeats_below_recommended", report.repeats_below_recommended()},
        {"threads", report.threads},
        {"triangle_test", report.triangle_test},
        {"slabs", report.slabs},
        {"reference", report.reference},
        {"embree_settings",
         report.embree_settings.empty() ? nlohmann::json(nullptr) : nlohmann::json(report.embree_settings)},
        {"embree_isa", report.embree_settings.empty() ? nlohmann::json(nullptr) : nlohmann::json(report.embree_isa)},
        {"isa_cap", report.isa_cap.empty() ? nlohmann::json(nullptr) : nlohmann::json(report.isa_cap)},
        {"sweep", report.sweep_name.empty()
                      ? nlohmann::json(nullptr)
                      : nlohmann::json{{"name", report.sweep_name}, {"parameter", report.sweep_parameter}}},
        {"notes", report.notes},
    };
    nlohmann::json rows = nlohmann::json::array();
    for (const BenchRow& row : report.rows) rows.push_back(json_row(row));
    json["rows"] = std::move(rows);
    std::ofstream out(path);
    if (!(out << json.dump(2) << "\n"))
        throw std::runtime_error(fmt::format("{}: cannot write the JSON file", path.string()));
}

}  // namespace trident::bench
