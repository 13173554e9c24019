#pragma once
// Runs every configuration the options name, scene by scene: for each thread count, Embree's rows
// (its build, then rtcIntersect1/4/8/16 on the same rays), then each structure (build repeated,
// then per traversal the render repeated, one counting pass, the error against the reference).
#include "bench/options.h"
#include "bench/report.h"

namespace trident::bench {

/// Throws SceneError or std::runtime_error with one line when a scene or reference cannot be
/// loaded; structures refused on a scene (the brute force above kBruteMaxTriangles) are named in
/// the report's notes.
BenchReport run_benchmark(const BenchOptions& options);

}  // namespace trident::bench
