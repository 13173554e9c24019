#pragma once
// What a benchmark run produced: one row per configuration (scene x structure x traversal x
// thread count, and the swept value in a sweep), plus what every output must state beside the
// figures (machine, resolution, repeats, reference). The writers only read this.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bench/machine.h"
#include "bench/statistics.h"

namespace trident::bench {

/// BENCHMARK.md's error figures against the reference trace.
struct ErrorFigures {
    double hit_miss_share = 0.0;
    double triangle_share = 0.0;
    double max_relative_t_difference = 0.0;
};

inline constexpr const char* kEmbreeStructure = "embree";

struct BenchRow {
    std::string scene, scene_source;
    std::size_t triangles = 0;
    double load_ms = 0.0;  // OBJ parsing or built-in generation, once per scene

    std::string structure;  // "bvh", "kdtree", "octree", "brute" or "embree"
    std::string traversal;  // ours: scalar / simd4 / simd8 / simd16; Embree: rtcIntersect1 / 4 / 8 / 16, stream8x8
    std::string triangle_test, slabs;  // ours: watertight / moller_trumbore, robust / fast; Embree: empty
    std::string builder;               // the BVHs': what built the tree (AccelStats::builder); empty elsewhere
    std::string ray_kind = "primary";  // the ray kind timed: primary, shadow or diffuse (bench/ray_sets.h)
    std::size_t ray_count = 0;         // rays traced per render when not W x H (secondary rays)
    int threads = 0;
    std::uint32_t width = 0, height = 0;
    int repeats = 0;

    Summary build_ms, render_ms;

    // Structure statistics and per-ray counts; Embree reports none of these but its memory.
    std::optional<std::size_t> nodes, leaves, max_depth, bytes;
    std::optional<double> sah_cost;
    std::optional<double> nodes_per_ray, triangles_per_ray;

    std::string reference;                  // what the error figures compare with
    std::optional<ErrorFigures> error;      // empty when there was no reference
    std::optional<double> ratio_to_embree;  // our Mrays/s over Embree's at the same rays and threads
    /// --scaling, rows at more than one thread: the median over the timed runs of (the render's
    /// time on one thread, taken right after) / (its time on this row's threads).
    std::optional<double> speedup_over_one_thread;
    /// --vs-single, packet rows of shadow and diffuse rays: the median over the timed runs of (the
    /// same rays' time as single rays, taken right after) / (this row's time).
    std::optional<double> speedup_over_single_rays;
    /// --paired, rows of ours: the median over the timed runs of (the partner's time on the same
    /// rays, taken right after) / (this row's time), so above 1 is faster than the partner.
    /// Partners: the same structure's scalar traversal (primary packet rows), the BVH at the same
    /// traversal (primary KD-tree and octree rows), Embree's call of the same width (every row:
    /// rtcIntersect1/N, rtcOccluded1/N for shadow rays), Embree's best for primary rays (the faster,
    /// run by run, of rtcIntersect16 and its stream rtcIntersect1M), the same traversal's closest
    /// hit on the same shadow rays (shadow rows).
    std::optional<double> paired_over_scalar, paired_over_bvh, paired_over_embree, paired_over_embree_best,
        paired_over_closest;

    std::string sweep_parameter;
    std::optional<double> sweep_value;
    std::string note;

    double rays() const { return ray_count ? double(ray_count) : double(width) * double(height); }
    /// Mrays/s of a render time: W * H / time.
    double mrays_per_s(double render_ms_value) const {
        return render_ms_value > 0 ? rays() / render_ms_value / 1000.0 : 0.0;
    }
    double mrays_per_s() const { return mrays_per_s(render_ms.median); }
    std::optional<double> bytes_per_triangle() const {
        if (!bytes || triangles == 0) return std::nullopt;
        return double(*bytes) / double(triangles);
    }
    bool is_embree() const { return structure == kEmbreeStructure; }
};

struct BenchReport {
    MachineInfo machine;
    std::string command_line;
    std::uint32_t width = 0, height = 0;
    int repeats = 0;
    std::vector<int> threads;
    std::string triangle_test;                // the triangle tests measured, comma separated
    std::string slabs;                        // the slab tests measured, comma separated
    std::string reference;                    // the reference the run chose; rows say where a scene differs
    std::string embree_settings;              // empty without Embree rows or partners
    std::string embree_isa;                   // --embree-isa: native, sse4.2, avx2 or avx512
    std::string isa_cap;                      // TRIDENT_ISA's cap on our kernels ("avx2"...), empty when none
    std::string sweep_name, sweep_parameter;  // empty unless --sweep
    std::vector<std::string> notes;           // refusals and other things a reader must know
    std::vector<BenchRow> rows;

    bool repeats_below_recommended() const { return repeats < kRecommendedRepeats; }
};

}  // namespace trident::bench
