#pragma once
// Runs a test body once per packet width this binary and this CPU can run, with the width's
// xsimd architecture as a template argument.
#include <doctest/doctest.h>

#include <string>

#include "simd/width.h"

namespace trident::testing {

/// Calls body.template operator()<Arch>() for every runnable packet width.
template <class Body>
void for_each_packet_arch(Body&& body) {
    for (const SimdWidth width : kSimdWidths) {
        if (width == SimdWidth::scalar || !is_runnable(width)) continue;
        const std::string width_name = to_string(width);
        CAPTURE(width_name);
        dispatch_width(width, [&]<SimdWidth W>() {
            if constexpr (W != SimdWidth::scalar && kArchInThisFile<W>) body.template operator()<ArchOf<W>>();
        });
    }
}

}  // namespace trident::testing
