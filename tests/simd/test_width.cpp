// SimdWidth: parsing and printing, what this build and CPU run, and dispatch on a run-time width.
#include <doctest/doctest.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <string_view>

#include "simd/width.h"

using namespace trident;

TEST_CASE("simd widths print as they parse and nothing else parses") {
    for (const SimdWidth width : kSimdWidths) {
        const std::string width_name = to_string(width);
        CAPTURE(width_name);
        CHECK(parse_simd_width(to_string(width)) == width);
    }
    CHECK(parse_simd_width("auto") == widest_supported());
    CHECK(std::string(to_string(SimdWidth::scalar)) == "scalar");
    CHECK(std::string(to_string(SimdWidth::w16)) == "16");
    std::size_t choices = 0;
    for (std::string_view rest = kSimdWidthChoices; !rest.empty(); ++choices) {
        const std::string_view choice = rest.substr(0, rest.find('|'));
        CAPTURE(std::string(choice));
        CHECK(parse_simd_width(choice).has_value());
        rest.remove_prefix(std::min(rest.size(), choice.size() + 1));
    }
    CHECK(choices == kSimdWidths.size() + 1);  // every width and "auto"
    for (const char* bad : {"", "2", "32", "AUTO", "Scalar", "8 ", "w8", "4x"}) {
        CAPTURE(bad);
        CHECK_FALSE(parse_simd_width(bad).has_value());
    }
}

TEST_CASE("widest_supported is runnable on this CPU and no wider width is") {
    const SimdWidth widest = widest_supported();
    const std::string widest_name = to_string(widest);
    CAPTURE(widest_name);
    CHECK(is_runnable(widest));
    CHECK(cpu_supports(widest));
    for (const SimdWidth width : kSimdWidths) {
        if (lane_count(width) > lane_count(widest)) CHECK_FALSE(is_runnable(width));
    }
    const auto cpu = xsimd::available_architectures();
    if (is_compiled_in(SimdWidth::w16) && cpu.avx512bw)
        CHECK(widest == SimdWidth::w16);
    else if (is_compiled_in(SimdWidth::w8) && cpu.avx2)
        CHECK(widest == SimdWidth::w8);
}

TEST_CASE("dispatch_width runs the body at the requested width and refuses widths it cannot run") {
    for (const SimdWidth width : kSimdWidths) {
        const std::string width_name = to_string(width);
        CAPTURE(width_name);
        auto lanes_of_body = [&]<SimdWidth W>() -> std::size_t {
            if constexpr (W == SimdWidth::scalar)
                return 1;
            else if constexpr (kArchInThisFile<W>)
                return xsimd::batch<float, ArchOf<W>>::size;
            else
                return lane_count(W);  // a kernel width this test file was not compiled for
        };
        if (is_runnable(width)) {
            CHECK(dispatch_width(width, lanes_of_body) == lane_count(width));
        } else {
            CHECK_THROWS_AS(dispatch_width(width, lanes_of_body), std::runtime_error);
        }
    }
}
