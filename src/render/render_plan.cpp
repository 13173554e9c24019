#include "render/render_plan.h"

#include <fmt/format.h>

#include <cmath>

namespace trident {
namespace {

std::string traversal_name(SimdWidth width) {
    return width == SimdWidth::scalar ? std::string("single rays") : fmt::format("{}-ray packets", lane_count(width));
}

std::string traversal_name(const StreamTraversal& t) {
    if (t.width == SimdWidth::scalar) return "single rays";
    return fmt::format("{}-ray packets {}", lane_count(t.width), to_string(t.grouping));
}

std::string vec_text(const Vec3f& v) { return fmt::format("({:.3g}, {:.3g}, {:.3g})", v.x, v.y, v.z); }

}  // namespace

const char* to_string(RenderMode mode) {
    switch (mode) {
        case RenderMode::shaded: return "shaded";
        case RenderMode::normal: return "normal";
        case RenderMode::depth: return "depth";
        case RenderMode::heat: return "heat";
        case RenderMode::ao: return "ao";
    }
    return "?";
}

std::optional<RenderMode> parse_render_mode(std::string_view name) {
    for (RenderMode mode : {RenderMode::shaded, RenderMode::normal, RenderMode::depth, RenderMode::heat, RenderMode::ao})
        if (name == to_string(mode)) return mode;
    return std::nullopt;
}

const char* to_string(HeatMeasure measure) { return measure == HeatMeasure::nodes ? "nodes" : "triangles"; }

std::optional<HeatMeasure> parse_heat_measure(std::string_view name) {
    if (name == "nodes") return HeatMeasure::nodes;
    if (name == "triangles") return HeatMeasure::triangles;
    return std::nullopt;
}

PointLight default_light(const Aabb& box) {
    const Vec3f e = box.extent();
    const float diagonal = length(e);
    const Vec3f c = box.center();
    return {Vec3f{c.x + 0.25f * e.x, box.hi.y + 0.5f * diagonal, c.z + 0.25f * e.z}};
}

StreamTraversal incoherent_traversal(AccelKind accel, SimdWidth requested, std::size_t triangles) {
    // Above this size, octree octant packets narrower than 16 lanes lost to single rays (render_plan.h).
    constexpr std::size_t kOctreeNarrowPacketTriangles = 100000;
    // Hinted as incoherent, as Embree's incoherent context flag (ray_stream.h).
    const auto single_rays = [] { return StreamTraversal{.coherence = RayCoherence::incoherent}; };
    if (requested == SimdWidth::scalar) return single_rays();
    const auto octant_packets = [](SimdWidth width) {
        return StreamTraversal{width, PacketGrouping::by_octant, SlabTest::robust, RayCoherence::incoherent};
    };
    switch (accel) {
        case AccelKind::bvh:
        case AccelKind::bvh2:
            if (is_runnable(SimdWidth::w16)) return octant_packets(SimdWidth::w16);
            return octant_packets(is_runnable(SimdWidth::w8) ? SimdWidth::w8 : requested);
        case AccelKind::kdtree:
            return octant_packets(is_runnable(SimdWidth::w16) ? SimdWidth::w16 : SimdWidth::w4);
        case AccelKind::octree:
            if (is_runnable(SimdWidth::w16)) return octant_packets(SimdWidth::w16);
            if (triangles >= kOctreeNarrowPacketTriangles) return single_rays();
            break;
        case AccelKind::brute:
            break;
    }
    return octant_packets(requested);
}

RenderPlan make_render_plan(const Scene& scene, const RenderRequest& request) {
    RenderPlan plan;
    std::vector<std::string>& why = plan.explanation;
    const bool benchmark = request.benchmark.has_value();
    const RenderMode mode = request.mode;
    plan.primary_width = request.width;

    // Normals: only what shades or shows a surface orientation needs them.
    const bool needs_normals =
        !benchmark && (mode == RenderMode::shaded || mode == RenderMode::normal || mode == RenderMode::ao);
    if (needs_normals)
        plan.normals = scene.mesh.has_normals() ? NormalSource::interpolated : NormalSource::geometric;
    plan.reads_barycentrics = plan.normals == NormalSource::interpolated;
    plan.shades = !benchmark && mode != RenderMode::heat;

    if (mode == RenderMode::heat && !benchmark) {
        why.push_back(fmt::format("primary: closest hit with traversal counters ({} per pixel), {}, {}",
                                  to_string(request.heat), traversal_name(request.width),
                                  request.width == SimdWidth::scalar
                                      ? "per ray"
                                      : "counted per packet: every lane of a packet shows the packet's count"));
        plan.counts_traversal = true;
        plan.heat = request.heat;
    } else {
        why.push_back(fmt::format("primary: closest hit, {}{}", traversal_name(request.width),
                                  benchmark ? ", visibility only (hit triangle and distance; timed)" : ""));
    }

    if (plan.normals == NormalSource::interpolated)
        why.push_back("normals: interpolated from the mesh's vertex normals (reads the hit barycentrics)");
    else if (plan.normals == NormalSource::geometric)
        why.push_back("normals: geometric (the mesh has no vertex normals; barycentrics unused)");
    else
        why.push_back(fmt::format("normals: skipped ({})", benchmark ? "visibility-only timing" : "the mode shows no surface shading"));

    // Shadow rays: to the scene's light; a benchmark without one uses the default light.
    const bool wants_shadows = benchmark ? request.benchmark->shadow : mode == RenderMode::shaded;
    if (wants_shadows && scene.light) {
        plan.light_source = LightSource::scene;
        plan.light = scene.light;
    } else if (wants_shadows && benchmark) {
        plan.light_source = LightSource::default_from_box;
        plan.light = default_light(scene.mesh.bounds());
    }
    plan.shadow_pass = plan.light.has_value();
    plan.shadow_traversal = {request.width, PacketGrouping::in_order};
    if (plan.shadow_pass)
        why.push_back(fmt::format("shadow: any-hit from every hit facing the light to the {} at {}, {} "
                                  "(lanes as the primary packets that made them), origins offset off the surface",
                                  plan.light_source == LightSource::scene
                                      ? "scene's light"
                                      : "default light (the scene has none: above the box by half its diagonal)",
                                  vec_text(plan.light->position), traversal_name(plan.shadow_traversal)));
    else if (mode == RenderMode::shaded && !benchmark)
        why.push_back("shadow: skipped (the scene has no light: headlight shading, nothing can be in shadow)");
    else
        why.push_back(fmt::format("shadow: skipped ({})", benchmark ? "shadow rays not asked for" : "the mode has no lighting"));

    // Ambient occlusion (image) or diffuse bounce rays (benchmark).
    plan.occlusion_traversal = incoherent_traversal(request.accel, request.width, scene.mesh.triangle_count());
    const float diagonal = length(scene.mesh.bounds().extent());
    if (benchmark && request.benchmark->diffuse) {
        plan.occlusion_pass = true;
        plan.occlusion_samples = 1;
        plan.occlusion_radius = kInfinity;
        why.push_back(fmt::format("diffuse: one cosine-distributed closest-hit ray per hit about the geometric normal, "
                                  "seeded per pixel, {}", traversal_name(plan.occlusion_traversal)));
    } else if (!benchmark && mode == RenderMode::ao) {
        plan.occlusion_pass = true;
        plan.occlusion_samples = request.ao_samples;
        plan.occlusion_radius = 0.1f * diagonal;
        why.push_back(fmt::format("ambient occlusion: {} cosine-distributed any-hit rays per hit about the shading "
                                  "normal, up to {:.3g} (a tenth of the scene's diagonal), seeded per pixel and sample, {}",
                                  plan.occlusion_samples, plan.occlusion_radius, traversal_name(plan.occlusion_traversal)));
    } else {
        why.push_back(fmt::format("ambient occlusion / diffuse: skipped ({})",
                                  benchmark ? "diffuse rays not asked for" : "only --mode ao traces them"));
    }

    if (benchmark)
        why.push_back("shade: skipped (visibility-only timing)");
    else if (mode == RenderMode::heat)
        why.push_back(fmt::format("shade: {} per pixel on a colour ramp with a legend", to_string(plan.heat)));
    else
        why.push_back(fmt::format("shade: {}", mode == RenderMode::shaded
                                                    ? (plan.shadow_pass ? "Lambert under the light, shadowed" : "headlight Lambert")
                                                    : to_string(mode)));
    return plan;
}

}  // namespace trident
