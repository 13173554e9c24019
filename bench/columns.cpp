#include "bench/columns.h"

#include <optional>
#include <vector>

namespace trident::bench {
namespace {

template <class T>
Cell optional_cell(const std::optional<T>& value) {
    if (!value) return std::monostate{};
    if constexpr (std::is_integral_v<T>)
        return std::int64_t(*value);
    else
        return double(*value);
}

Cell error_cell(const BenchRow& row, double ErrorFigures::*figure) {
    if (!row.error) return std::monostate{};
    return (*row.error).*figure;
}

Cell text_cell(const std::string& text) { return text.empty() ? Cell{} : Cell{text}; }

}  // namespace

std::span<const Column> row_columns() {
    static const std::vector<Column> columns = {
        {"scene", [](const BenchRow& r) -> Cell { return r.scene; }},
        {"scene_source", [](const BenchRow& r) -> Cell { return r.scene_source; }},
        {"triangles", [](const BenchRow& r) -> Cell { return std::int64_t(r.triangles); }},
        {"load_ms", [](const BenchRow& r) -> Cell { return r.load_ms; }},
        {"structure", [](const BenchRow& r) -> Cell { return r.structure; }},
        {"traversal", [](const BenchRow& r) -> Cell { return r.traversal; }},
        {"rays", [](const BenchRow& r) -> Cell { return r.ray_kind; }},
        {"triangle_test", [](const BenchRow& r) { return text_cell(r.triangle_test); }},
        {"slabs", [](const BenchRow& r) { return text_cell(r.slabs); }},
        {"builder", [](const BenchRow& r) { return text_cell(r.builder); }},
        {"threads", [](const BenchRow& r) -> Cell { return std::int64_t(r.threads); }},
        {"width", [](const BenchRow& r) -> Cell { return std::int64_t(r.width); }},
        {"height", [](const BenchRow& r) -> Cell { return std::int64_t(r.height); }},
        {"repeats", [](const BenchRow& r) -> Cell { return std::int64_t(r.repeats); }},
        {"build_ms", [](const BenchRow& r) -> Cell { return r.build_ms.median; }},
        {"build_ms_min", [](const BenchRow& r) -> Cell { return r.build_ms.min; }},
        {"build_ms_max", [](const BenchRow& r) -> Cell { return r.build_ms.max; }},
        {"render_ms", [](const BenchRow& r) -> Cell { return r.render_ms.median; }},
        {"render_ms_min", [](const BenchRow& r) -> Cell { return r.render_ms.min; }},
        {"render_ms_max", [](const BenchRow& r) -> Cell { return r.render_ms.max; }},
        {"mrays_per_s", [](const BenchRow& r) -> Cell { return r.mrays_per_s(); }},
        // The slowest render gives the fewest rays per second.
        {"mrays_per_s_min", [](const BenchRow& r) -> Cell { return r.mrays_per_s(r.render_ms.max); }},
        {"mrays_per_s_max", [](const BenchRow& r) -> Cell { return r.mrays_per_s(r.render_ms.min); }},
        {"nodes", [](const BenchRow& r) { return optional_cell(r.nodes); }},
        {"leaves", [](const BenchRow& r) { return optional_cell(r.leaves); }},
        {"max_depth", [](const BenchRow& r) { return optional_cell(r.max_depth); }},
        {"sah_cost", [](const BenchRow& r) { return optional_cell(r.sah_cost); }},
        {"bytes", [](const BenchRow& r) { return optional_cell(r.bytes); }},
        {"bytes_per_triangle", [](const BenchRow& r) { return optional_cell(r.bytes_per_triangle()); }},
        {"nodes_per_ray", [](const BenchRow& r) { return optional_cell(r.nodes_per_ray); }},
        {"triangles_per_ray", [](const BenchRow& r) { return optional_cell(r.triangles_per_ray); }},
        {"reference", [](const BenchRow& r) { return text_cell(r.reference); }},
        {"hit_miss_share", [](const BenchRow& r) { return error_cell(r, &ErrorFigures::hit_miss_share); }},
        {"triangle_share", [](const BenchRow& r) { return error_cell(r, &ErrorFigures::triangle_share); }},
        {"max_relative_t_difference",
         [](const BenchRow& r) { return error_cell(r, &ErrorFigures::max_relative_t_difference); }},
        {"ratio_to_embree", [](const BenchRow& r) { return optional_cell(r.ratio_to_embree); }},
        {"speedup_over_one_thread", [](const BenchRow& r) { return optional_cell(r.speedup_over_one_thread); }},
        {"speedup_over_single_rays", [](const BenchRow& r) { return optional_cell(r.speedup_over_single_rays); }},
        {"paired_over_scalar", [](const BenchRow& r) { return optional_cell(r.paired_over_scalar); }},
        {"paired_over_bvh", [](const BenchRow& r) { return optional_cell(r.paired_over_bvh); }},
        {"paired_over_embree", [](const BenchRow& r) { return optional_cell(r.paired_over_embree); }},
        {"paired_over_embree_best", [](const BenchRow& r) { return optional_cell(r.paired_over_embree_best); }},
        {"paired_over_closest", [](const BenchRow& r) { return optional_cell(r.paired_over_closest); }},
        {"sweep_parameter", [](const BenchRow& r) { return text_cell(r.sweep_parameter); }},
        {"sweep_value", [](const BenchRow& r) { return optional_cell(r.sweep_value); }},
        {"note", [](const BenchRow& r) { return text_cell(r.note); }},
    };
    return columns;
}

}  // namespace trident::bench
