// The header-only pieces of trident-bench: repeated timing statistics and the traversal names.
#include <doctest/doctest.h>

#include <vector>

#include "bench/statistics.h"
#include "bench/traversal.h"

using namespace trident::bench;

TEST_CASE("summarize gives the median (mean of the middle two for an even count), min and max") {
    const Summary odd = summarize({5.0, 1.0, 3.0});
    CHECK(odd.median == 3.0);
    CHECK(odd.min == 1.0);
    CHECK(odd.max == 5.0);
    CHECK(odd.samples == std::vector<double>{5.0, 1.0, 3.0});  // kept in the order taken
    const Summary even = summarize({4.0, 1.0, 2.0, 10.0});
    CHECK(even.median == 3.0);
    CHECK(summarize({7.0}).median == 7.0);
    CHECK_THROWS(summarize({}));
}

TEST_CASE("measure_repeated runs one warm-up that does not count, then the repeats") {
    std::vector<int> runs;
    const Summary summary = measure_repeated(3, [&](int run) {
        runs.push_back(run);
        return run == 0 ? 1000.0 : double(run);  // the warm-up is slow and must be dropped
    });
    CHECK(runs == std::vector<int>{0, 1, 2, 3});
    CHECK(summary.samples == std::vector<double>{1.0, 2.0, 3.0});
    CHECK(summary.max == 3.0);
    CHECK_THROWS(measure_repeated(0, [](int) { return 0.0; }));
}

TEST_CASE("traversal names parse in both spellings and round-trip") {
    for (Traversal t : kAllTraversals) CHECK(parse_traversal(to_string(t)) == t);
    CHECK(parse_traversal("8") == Traversal::simd8);
    CHECK(simd_width(*parse_traversal("auto")) == trident::widest_supported());
    CHECK_FALSE(parse_traversal("7").has_value());
    CHECK_FALSE(parse_traversal("").has_value());
    CHECK(rays_per_call(Traversal::simd16) == 16);
    CHECK(is_runnable(Traversal::scalar));
}
