#pragma once
// Turning the run-time choice of triangle test and slab test into compile-time ones, so kernels
// are instantiated per variant rather than branching per triangle or per box.
#include <type_traits>

#include "core/intersect_triangle.h"
#include "core/slab_test.h"

namespace trident {

/// Calls f(std::integral_constant<TriangleTest, T>{}) for the run-time choice.
template <class F>
decltype(auto) with_triangle_test(TriangleTest test, F&& f) {
    if (test == TriangleTest::moller_trumbore)
        return f(std::integral_constant<TriangleTest, TriangleTest::moller_trumbore>{});
    return f(std::integral_constant<TriangleTest, TriangleTest::watertight>{});
}

/// Calls f(std::integral_constant<TriangleTest, T>{}, std::integral_constant<SlabTest, S>{}) for
/// the run-time choices: the 2 x 2 grid of traversal variants the benchmark compares (issue 8).
template <class F>
decltype(auto) with_traversal_variant(TriangleTest test, SlabTest slabs, F&& f) {
    return with_triangle_test(test, [&](auto test_tag) -> decltype(auto) {
        if (slabs == SlabTest::fast) return f(test_tag, std::integral_constant<SlabTest, SlabTest::fast>{});
        return f(test_tag, std::integral_constant<SlabTest, SlabTest::robust>{});
    });
}

}  // namespace trident
