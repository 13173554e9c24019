#include "stress/stress_runner.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <span>

#include "core/reference.h"
#include "render/ray_stream.h"
#include "stress/hit_judge.h"

namespace trident {

const char* to_string(StressQuery query) { return query == StressQuery::closest_hit ? "closest" : "any"; }

std::vector<SimdWidth> runnable_widths() {
    std::vector<SimdWidth> widths;
    for (SimdWidth width : kSimdWidths)
        if (is_runnable(width)) widths.push_back(width);
    return widths;
}

namespace {

/// The double-precision closest hits of every stride-th ray, and which triangles have zero area.
struct CaseReference {
    std::vector<Triangle> triangles;
    std::vector<std::uint8_t> degenerate;
    std::size_t stride = 1;
    std::vector<ReferenceHit> hits;  // hits[k]: ray k * stride

    CaseReference(const StressCase& c, std::uint64_t budget) : triangles(gather_triangles(c.mesh)) {
        for (const Triangle& tri : triangles) {
            const Vec3d e1 = Vec3d(tri.b) - Vec3d(tri.a), e2 = Vec3d(tri.c) - Vec3d(tri.a);
            degenerate.push_back(cross(e1, e2) == Vec3d(0.0) ? 1 : 0);
        }
        const std::uint64_t work = std::uint64_t(c.rays.size()) * std::max<std::size_t>(triangles.size(), 1);
        stride = std::size_t(std::max<std::uint64_t>(1, (work + budget - 1) / budget));
        hits.resize((c.rays.size() + stride - 1) / stride);
        tbb::parallel_for(std::size_t(0), hits.size(),
                          [&](std::size_t k) { hits[k] = trace_reference(triangles, c.rays[k * stride]); });
    }

    const ReferenceHit* at(std::size_t ray) const { return ray % stride == 0 ? &hits[ray / stride] : nullptr; }
};

bool finite_hit(const Hit& h) { return std::isfinite(h.t) && std::isfinite(h.u) && std::isfinite(h.v); }

void judge_closest(const StressCase& c, const CaseReference& ref, std::span<const Hit> hits, StressTally& tally) {
    for (std::size_t i = 0; i < hits.size(); ++i) {
        const Hit& h = hits[i];
        const Ray& ray = c.rays[i];
        if (h.is_hit()) {
            if (!finite_hit(h)) { ++tally.non_finite; continue; }
            if (h.triangle >= ref.triangles.size() || ref.degenerate[h.triangle] || h.triangle == c.start_triangle[i]) {
                ++tally.triangle_disagreements;
                continue;
            }
        } else if (c.must_hit[i]) {
            ++tally.leaks;
            continue;
        }
        const ReferenceHit* r = ref.at(i);
        if (!r) continue;
        ++tally.reference_rays;
        if (h.is_hit() != r->is_hit()) {
            const bool tolerated = h.is_hit() ? fit_triangle(ray, ref.triangles[h.triangle]).may_hit(ray)
                                              : !some_triangle_must_hit(ref.triangles, ray);
            if (!tolerated) ++tally.hit_miss_disagreements;
            continue;
        }
        if (!h.is_hit()) continue;
        const double error = std::abs(double(h.t) - r->t);
        const TriangleFit mine = fit_triangle(ray, ref.triangles[h.triangle]);
        double allowed = mine.t_tolerance;
        if (h.triangle != r->triangle) {
            // Agreement when the two hits tie (shared edge or vertex, duplicate, crossing), or
            // when one of them lies within the tolerance of an edge, where the float test and the
            // reference may each keep or drop it: a ray touching a solid at a vertex, or a near
            // hit on the far side of an edge. Anything else is a wrong triangle.
            const TriangleFit theirs = fit_triangle(ray, ref.triangles[r->triangle]);
            const bool tie = mine.may_hit(ray) && std::abs(mine.t - r->t) <= mine.t_tolerance + theirs.t_tolerance;
            const bool edge_case = mine.may_hit(ray) && (h.t < r->t ? !mine.must_hit(ray) : !theirs.must_hit(ray));
            if (!tie && !edge_case) {
                ++tally.triangle_disagreements;
                continue;
            }
            if (!tie) continue;  // two different surfaces: no t error to speak of
            allowed += theirs.t_tolerance;
        }
        tally.max_relative_t_error = std::max(tally.max_relative_t_error, error / std::max(r->t, 1e-30));
        if (error > allowed) ++tally.t_beyond_tolerance;
    }
}

void judge_any(const StressCase& c, const CaseReference& ref, std::span<const std::uint8_t> occluded,
               StressTally& tally) {
    for (std::size_t i = 0; i < occluded.size(); ++i) {
        const Ray& ray = c.rays[i];
        if (!occluded[i] && c.must_hit[i]) {
            ++tally.leaks;
            continue;
        }
        const ReferenceHit* r = ref.at(i);
        if (!r) continue;
        ++tally.reference_rays;
        if (bool(occluded[i]) == r->is_hit()) continue;
        const bool tolerated = occluded[i] ? some_triangle_may_hit(ref.triangles, ray)
                                           : !some_triangle_must_hit(ref.triangles, ray);
        if (!tolerated) ++tally.hit_miss_disagreements;
    }
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

void run_stress_case(const StressCase& stress_case, const StressRunOptions& options,
                     const std::function<void(const StressTally&)>& report) {
    const CaseReference reference(stress_case, options.reference_tests);
    const std::vector<SimdWidth> widths = options.widths.empty() ? runnable_widths() : options.widths;
    for (AccelKind kind : options.accels) {
        const AnyAccel accel = AnyAccel::build(kind, stress_case.mesh, options.accel_options);
        const std::size_t ray_count =
            kind == AccelKind::brute ? std::min(options.brute_rays, stress_case.rays.size()) : stress_case.rays.size();
        const std::span<const Ray> rays(stress_case.rays.data(), ray_count);
        for (SimdWidth width : widths) {
            const StreamTraversal traversal{width, PacketGrouping::in_order, options.slabs};
            for (StressQuery query : {StressQuery::closest_hit, StressQuery::any_hit}) {
                StressTally tally{stress_case.name, kind, width, query};
                tally.rays = ray_count;
                const auto start = std::chrono::steady_clock::now();
                if (query == StressQuery::closest_hit) {
                    std::vector<Hit> hits(rays.size());
                    intersect_stream_parallel(accel, rays, hits, traversal, options.test);
                    tally.trace_seconds = seconds_since(start);
                    judge_closest(stress_case, reference, hits, tally);
                } else {
                    std::vector<std::uint8_t> occluded(rays.size());
                    occlude_stream_parallel(accel, rays, occluded, traversal, options.test);
                    tally.trace_seconds = seconds_since(start);
                    judge_any(stress_case, reference, occluded, tally);
                }
                report(tally);
            }
        }
    }
}

}  // namespace trident
