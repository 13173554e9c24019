#pragma once
// Runs a stress case over every structure, traversal width and query (closest hit, any hit) and
// tallies what went wrong: leaks (a ray that must hit and did not), hit/miss and triangle
// disagreements with the double-precision reference beyond the tolerances of hit_judge.h, hits
// on zero-area triangles or on the triangle a ray starts from, non-finite hits, and the largest
// relative t error. The reference is computed once per case and shared by every configuration.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "accel/any_accel.h"
#include "core/intersect_triangle.h"
#include "core/slab_test.h"
#include "simd/width.h"
#include "stress/stress_case.h"

namespace trident {

enum class StressQuery { closest_hit, any_hit };
const char* to_string(StressQuery query);

struct StressRunOptions {
    std::vector<AccelKind> accels = built_accel_kinds();
    AccelOptions accel_options;     // the wide BVH's width among them (--bvh-width)
    std::vector<SimdWidth> widths;  // empty: every width this CPU runs
    TriangleTest test = TriangleTest::watertight;
    SlabTest slabs = SlabTest::robust;
    /// The brute force is a sanity row: it traces only the case's first brute_rays rays.
    std::size_t brute_rays = 20000;
    /// Ray-triangle tests in double per case: rays are checked against the reference at a stride
    /// that keeps within it (every ray on small cases). Leak, degenerate and start-triangle checks
    /// need no reference and cover every ray.
    std::uint64_t reference_tests = 300'000'000;
};

struct StressTally {
    std::string case_name;
    AccelKind accel = AccelKind::bvh;
    SimdWidth width = SimdWidth::scalar;
    StressQuery query = StressQuery::closest_hit;
    std::size_t rays = 0;            // rays traced
    std::size_t reference_rays = 0;  // of which compared with the reference
    std::size_t leaks = 0;
    std::size_t hit_miss_disagreements = 0;
    std::size_t triangle_disagreements = 0;  // wrong triangle, a zero-area one, or the ray's start triangle
    std::size_t t_beyond_tolerance = 0;
    std::size_t non_finite = 0;  // hits with a NaN or infinite t, u or v
    double max_relative_t_error = 0.0;
    double trace_seconds = 0.0;

    double mrays_per_s() const { return trace_seconds > 0.0 ? double(rays) / trace_seconds * 1e-6 : 0.0; }
    std::size_t failures() const {
        return leaks + hit_miss_disagreements + triangle_disagreements + t_beyond_tolerance + non_finite;
    }
};

/// The widths this CPU and binary run, scalar first.
std::vector<SimdWidth> runnable_widths();

/// Traces `stress_case` with every configuration of `options`, calling report() after each.
void run_stress_case(const StressCase& stress_case, const StressRunOptions& options,
                     const std::function<void(const StressTally&)>& report);

}  // namespace trident
