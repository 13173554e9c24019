#pragma once
// What a render or a benchmark run must trace and compute, derived once from the scene and the
// request, so the renderer does no work the result does not need: no shadow pass without a
// light, no normal interpolation without vertex normals, no barycentrics or shading when only
// visibility is timed, any-hit traversal for every occlusion query.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "accel/any_accel.h"
#include "core/scene.h"
#include "render/ray_stream.h"
#include "simd/width.h"

namespace trident {

enum class RenderMode { shaded, normal, depth, heat, ao };
/// What a heat map counts per pixel.
enum class HeatMeasure { nodes, triangles };

const char* to_string(RenderMode mode);
std::optional<RenderMode> parse_render_mode(std::string_view name);
const char* to_string(HeatMeasure measure);
std::optional<HeatMeasure> parse_heat_measure(std::string_view name);

/// The secondary ray kinds a benchmark times besides primary rays.
struct BenchmarkRays {
    bool shadow = false;   // any-hit toward the light
    bool diffuse = false;  // one cosine-distributed closest-hit ray per primary hit
};

struct RenderRequest {
    RenderMode mode = RenderMode::shaded;
    std::optional<BenchmarkRays> benchmark;  // set: visibility-only timing, no image
    AccelKind accel = AccelKind::bvh;
    SimdWidth width = SimdWidth::scalar;
    std::uint32_t ao_samples = 16;
    HeatMeasure heat = HeatMeasure::nodes;
};

enum class NormalSource { none, geometric, interpolated };
enum class LightSource { none, scene, default_from_box };

struct RenderPlan {
    SimdWidth primary_width = SimdWidth::scalar;
    bool reads_barycentrics = false;    // only to interpolate vertex normals
    NormalSource normals = NormalSource::none;
    bool shades = false;                // false: visibility-only (benchmark), or a mode that only maps a figure
    LightSource light_source = LightSource::none;
    std::optional<PointLight> light;    // the light shadow rays go to
    bool shadow_pass = false;
    StreamTraversal shadow_traversal;
    bool occlusion_pass = false;        // ambient occlusion (image) or diffuse rays (benchmark)
    std::uint32_t occlusion_samples = 0;
    float occlusion_radius = 0.0f;      // AO: rays end here; diffuse benchmark rays: infinite
    StreamTraversal occlusion_traversal;
    bool counts_traversal = false;      // heat maps
    HeatMeasure heat = HeatMeasure::nodes;

    /// One line per pass: what runs or is skipped, and why (`trident render --explain`).
    std::vector<std::string> explanation;
};

/// The default light of a scene without one (benchmark shadow rays): above the box's top face by
/// half its diagonal, shifted off the vertical axis by a quarter of the box on x and z so shadows
/// fall sideways.
PointLight default_light(const Aabb& box);

/// Cosine-distributed rays are incoherent. Whenever packets are asked for (any width but scalar),
/// this is, per structure, the octant-packet width measured faster than single rays on every one
/// of the study's scenes (`trident-bench --rays diffuse --vs-single`, which times each packet run
/// and a single-ray run of the same rays in pairs; bench/experiments/shadow-diffuse.md, "Diffuse rays: which
/// traversal"): the BVH takes 16 lanes where they run (1.20-3.32x in three runs at 9fd447c, ahead
/// of 8 lanes on every scene; at 44f3868, before its packet walk got faster, 16 lanes fell to
/// 1.01x on Gallery and 8 were chosen), else 8 (1.10-2.42x; 4 lanes lost on Gallery at
/// 44f3868); the KD-tree 16 lanes where they run (1.07-2.42x), else 4 (8 lanes lost on Room and
/// Buddha); the octree 16 lanes where they run (1.07-2.66x), else single rays above 100k
/// triangles (narrower packets lost by up to 10% on Sponza, Room and Gallery) and the asked width
/// below. Any choice gives the same answers, bit for bit. The rays are hinted incoherent
/// (StreamTraversal::coherence): the wide BVH prefetches for them, and over a large tree its
/// packets go ray by ray from the start.
StreamTraversal incoherent_traversal(AccelKind accel, SimdWidth requested, std::size_t triangles);

RenderPlan make_render_plan(const Scene& scene, const RenderRequest& request);

}  // namespace trident
