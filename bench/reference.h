#pragma once
// The reference trace the error columns compare with (BENCHMARK.md's "error"): Embree when it is
// built (an independent tracer), else our BVH, else the brute force; or a hit buffer another
// tracer wrote; or, with `self`, each configuration's own trace (its error must be exactly zero).
#include <optional>
#include <string>

#include "bench/options.h"
#include "bench/report.h"
#include "camera/camera.h"
#include "core/scene.h"
#include "render/hit_buffer.h"

namespace trident::bench {

struct ReferenceTrace {
    std::string description;        // stated beside every error figure
    std::optional<HitBuffer> hits;  // empty with `self`, and when no reference could be traced
    bool self = false;
};

/// `automatic` resolved for this binary (Embree, else BVH, else brute force).
ReferenceChoice resolve_automatic(const ReferenceChoice& choice);

/// What the run compares with, before any scene is loaded (for the report's header).
std::string describe_reference(const ReferenceChoice& choice);

/// Traces (or reads) the reference for one scene. Throws std::runtime_error naming the file when
/// a reference hit buffer cannot be read or does not match the image size.
ReferenceTrace make_reference(const ReferenceChoice& choice, const Scene& scene, const Camera& camera);

/// The error figures of `hits` against the reference; empty when there is none.
std::optional<ErrorFigures> error_against(const ReferenceTrace& reference, const HitBuffer& hits);

}  // namespace trident::bench
