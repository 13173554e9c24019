#pragma once
// Compares a structure's closest hits with the double-precision brute force. Agreement means the
// same hit or miss and the same distance within a relative tolerance; a different triangle is
// accepted when the reference also hits that triangle at (nearly) the same distance, which is a
// tie between triangles sharing an edge or a vertex, or duplicates.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "core/reference.h"

namespace trident::testing {

/// Relative tolerance on t: the float watertight test is within a few ulps of the double one
/// for well-conditioned hits; 1e-4 leaves room for grazing hits far from the origin.
inline constexpr double kRelativeTTolerance = 1e-4;

struct AgreementReport {
    std::size_t rays = 0, hit_miss_disagreements = 0, t_disagreements = 0, triangle_disagreements = 0;
    std::string first_problem;
};

inline bool nearly_equal_t(double a, double b) {
    return std::abs(a - b) <= kRelativeTTolerance * std::max({1.0, std::abs(a), std::abs(b)});
}

/// Checks `hits[i]` (from the structure under test) against the reference for `rays[i]`.
template <class HitT>
AgreementReport compare_with_reference(std::span<const Triangle> triangles, std::span<const Ray> rays,
                                       std::span<const HitT> hits) {
    AgreementReport report;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ++report.rays;
        const ReferenceHit ref = trace_reference(triangles, rays[i]);
        const HitT& hit = hits[i];
        auto note = [&](const char* what) {
            if (report.first_problem.empty())
                report.first_problem = std::string(what) + " at ray " + std::to_string(i);
        };
        if (ref.is_hit() != hit.is_hit()) {
            // A miss/hit at the very edge of a triangle where the reference hits at t and the
            // structure finds nothing is a real leak; we count it.
            ++report.hit_miss_disagreements;
            note("hit/miss");
            continue;
        }
        if (!ref.is_hit()) continue;
        if (!nearly_equal_t(ref.t, hit.t)) {
            ++report.t_disagreements;
            note("t");
            continue;
        }
        if (hit.triangle != ref.triangle) {
            const double t_other = intersect_reference(rays[i], triangles[hit.triangle]);
            if (!nearly_equal_t(t_other, ref.t)) {
                ++report.triangle_disagreements;
                note("triangle");
            }
        }
    }
    return report;
}

inline void require_agreement(const AgreementReport& report) {
    INFO("rays ", report.rays, ", first problem: ", report.first_problem);
    CHECK(report.hit_miss_disagreements == 0);
    CHECK(report.t_disagreements == 0);
    CHECK(report.triangle_disagreements == 0);
}

}  // namespace trident::testing
