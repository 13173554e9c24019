#include "bench/reference.h"

#include <fmt/format.h>
#include <tbb/info.h>

#include <filesystem>
#include <stdexcept>

#include "accel/any_accel.h"
#include "bench/embree_baseline.h"
#include "render/trace.h"

namespace trident::bench {
namespace {

using Source = ReferenceChoice::Source;

HitBuffer trace_with_embree(const Scene& scene, const Camera& camera) {
#if TRIDENT_HAVE_EMBREE
    const EmbreeDevice device(tbb::info::default_concurrency());
    const EmbreeScene embree_scene(device, scene.mesh);
    std::vector<Hit> hits(std::size_t(camera.width()) * camera.height());
    embree_scene.trace(camera, 1, hits);
    return make_hit_buffer(camera.width(), camera.height(), hits);
#else
    (void)scene, (void)camera;
    throw std::logic_error("Embree reference requested in a binary built without Embree");
#endif
}

HitBuffer read_reference_file(const std::filesystem::path& given, const Scene& scene, const Camera& camera) {
    const std::filesystem::path path =
        std::filesystem::is_directory(given) ? given / fmt::format("{}.hits", scene.name) : given;
    HitBuffer buffer = read_hit_buffer(path);
    if (buffer.width != camera.width() || buffer.height != camera.height())
        throw std::runtime_error(fmt::format("--reference-hits {}: {}x{} rays, but this run traces {}x{}",
                                             path.string(), buffer.width, buffer.height, camera.width(),
                                             camera.height()));
    return buffer;
}

}  // namespace

ReferenceChoice resolve_automatic(const ReferenceChoice& choice) {
    if (choice.source != Source::automatic) return choice;
    ReferenceChoice resolved;
    if (kHaveEmbree) {
        resolved.source = Source::embree;
    } else {
        resolved.source = Source::structure;
        resolved.structure = AccelKind::bvh;
    }
    return resolved;
}

std::string describe_reference(const ReferenceChoice& choice) {
    const ReferenceChoice resolved = resolve_automatic(choice);
    switch (resolved.source) {
        case Source::embree:
#if TRIDENT_HAVE_EMBREE
            return fmt::format("embree rtcIntersect1 ({})", embree_settings(EmbreeQuality::high));
#else
            return "embree";
#endif
        case Source::structure:
            return fmt::format("{} (scalar, watertight)", to_string(resolved.structure));
        case Source::self:
            return "self (each configuration against its own trace)";
        case Source::file:
            return fmt::format("hit buffer {}", resolved.file.string());
        case Source::automatic:
            break;
    }
    return "none";
}

ReferenceTrace make_reference(const ReferenceChoice& choice, const Scene& scene, const Camera& camera) {
    const ReferenceChoice resolved = resolve_automatic(choice);
    ReferenceTrace reference{describe_reference(resolved), std::nullopt, false};
    switch (resolved.source) {
        case Source::self:
            reference.self = true;
            break;
        case Source::embree:
            reference.hits = trace_with_embree(scene, camera);
            break;
        case Source::file:
            reference.hits = read_reference_file(resolved.file, scene, camera);
            break;
        case Source::structure:
            if (resolved.structure == AccelKind::brute && scene.mesh.triangle_count() > kBruteMaxTriangles) {
                reference.description =
                    fmt::format("none (the brute-force reference is refused above {} triangles)", kBruteMaxTriangles);
                break;
            }
            reference.hits = make_hit_buffer(camera.width(), camera.height(),
                                             trace_primary(AnyAccel::build(resolved.structure, scene.mesh), camera));
            break;
        case Source::automatic:
            break;
    }
    return reference;
}

std::optional<ErrorFigures> error_against(const ReferenceTrace& reference, const HitBuffer& hits) {
    const HitBuffer* compared_with = reference.self ? &hits : reference.hits ? &*reference.hits : nullptr;
    if (!compared_with) return std::nullopt;
    const HitBufferComparison comparison = compare_hit_buffers(hits, *compared_with);
    return ErrorFigures{comparison.hit_miss_share(), comparison.triangle_share(), comparison.max_relative_t_difference};
}

}  // namespace trident::bench
