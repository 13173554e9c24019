#pragma once
// Repeated timing as BENCHMARK.md asks: one warm-up run that is thrown away, then `repeats`
// timed runs summarized by their median, with the minimum and maximum kept beside it.
#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <vector>

namespace trident::bench {

inline constexpr int kWarmupRuns = 1;
/// BENCHMARK.md's minimum; fewer repeats are allowed for smoke runs and said so in every output.
inline constexpr int kRecommendedRepeats = 5;

struct Summary {
    double median = 0.0, min = 0.0, max = 0.0;
    std::vector<double> samples;  // in the order they were taken
};

/// Median (mean of the two middle samples for an even count), min and max; throws on no samples.
inline Summary summarize(std::vector<double> samples) {
    if (samples.empty()) throw std::invalid_argument("summarize: no samples");
    Summary summary;
    summary.samples = samples;
    std::sort(samples.begin(), samples.end());
    const std::size_t n = samples.size();
    summary.median = n % 2 ? samples[n / 2] : 0.5 * (samples[n / 2 - 1] + samples[n / 2]);
    summary.min = samples.front();
    summary.max = samples.back();
    return summary;
}

inline double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// Calls run(i) for i = 0 (the warm-up) .. repeats; each call returns the milliseconds it
/// measured (a structure reports its own build time, a trace is timed around the call).
template <class Run>
Summary measure_repeated(int repeats, Run&& run) {
    if (repeats < 1) throw std::invalid_argument("measure_repeated: repeats must be at least 1");
    for (int i = 0; i < kWarmupRuns; ++i) run(i);
    std::vector<double> samples;
    samples.reserve(std::size_t(repeats));
    for (int i = 0; i < repeats; ++i) samples.push_back(run(kWarmupRuns + i));
    return summarize(std::move(samples));
}

}  // namespace trident::bench
