// trident: render, inspect and list scenes with a chosen acceleration structure.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include "accel/any_accel.h"
#include "accel/kdtree/kd_node.h"
#include "cli/stress_command.h"
#include "camera/camera.h"
#include "render/heat_map.h"
#include "render/hit_buffer.h"
#include "render/render_plan.h"
#include "render/shade.h"
#include "render/trace.h"
#include "scene/manifest.h"
#include "scene/scene_error.h"
#include "scene/scene_source.h"
#include "scenes/builtin.h"
#include "simd/cpu_info.h"

namespace trident {
namespace {

constexpr std::uint32_t kMaxImageSide = 16384;

struct CommonOptions {
    std::string scene;
    std::optional<std::filesystem::path> manifest;
    std::string accel = "bvh";
    std::string triangle_test = "watertight";
    int threads = 0;
    AccelOptions accel_options;
};

struct RenderOptions {
    std::string simd = "auto";
    std::string slabs = "robust";
    std::uint32_t width = 1920, height = 1080;
    std::string mode = "shaded";
    std::filesystem::path output = "render.png";
    std::optional<std::filesystem::path> dump_hits;
    std::uint32_t ao_samples = 16;
    std::string heat = "nodes";
    bool explain = false;
};

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

AccelKind accel_kind_or_throw(const std::string& name) {
    const auto kind = parse_accel_kind(name);
    if (!kind) throw std::invalid_argument(fmt::format("--accel {}: unknown structure (brute, bvh, bvh2, kdtree, octree)", name));
    return *kind;
}

TriangleTest triangle_test_or_throw(const std::string& name) {
    if (const auto test = parse_triangle_test(name)) return *test;
    throw std::invalid_argument(fmt::format("--triangle-test {}: expected watertight or moller_trumbore", name));
}

SlabTest slab_test_or_throw(const std::string& name) {
    if (const auto slabs = parse_slab_test(name)) return *slabs;
    throw std::invalid_argument(fmt::format("--slabs {}: expected robust or fast", name));
}

SimdWidth simd_width_or_throw(const std::string& name) {
    const auto width = parse_simd_width(name);
    if (!width) throw std::invalid_argument(fmt::format("--simd {}: expected {}", name, kSimdWidthChoices));
    if (!is_runnable(*width)) throw std::invalid_argument(fmt::format("--simd {}: {}", name, unavailable_reason(*width)));
    return *width;
}

/// Builds the structure and prints, on stderr, what its builder had to give up (the octree's
/// reference guard), so a user never takes a truncated tree for the real thing.
AnyAccel build_and_warn(AccelKind kind, const Mesh& mesh, const AccelOptions& options) {
    AnyAccel accel = AnyAccel::build(kind, mesh, options);
    accel.visit([](const auto& structure) {
        if constexpr (requires { structure.warning(); })
            if (!structure.warning().empty()) std::fprintf(stderr, "trident: warning: %s\n", structure.warning().c_str());
    });
    return accel;
}

void add_common_options(CLI::App& command, CommonOptions& common, bool with_accel) {
    command.add_option("scene", common.scene, "built-in scene name, path to an .obj file, or a name in --scenes")->required();
    command.add_option("--scenes", common.manifest, "scene manifest (scenes.json) to look the scene up in");
    if (with_accel) {
        command.add_option("--accel", common.accel,
                           "acceleration structure: brute|bvh|bvh2|kdtree|octree (bvh: the wide BVH, bvh2: the "
                           "binary one)");
        command.add_option("--bvh-width", common.accel_options.bvh.width,
                           "BVH: children per node, 2 (binary), 4, 8 or 16 (default: 16 where AVX2 runs, else 8)")
            ->check(CLI::IsMember({2, 4, 8, 16}));
        command.add_option("--triangle-test", common.triangle_test, "watertight (default) or moller_trumbore");
        command.add_option("--octree-depth", common.accel_options.octree.max_depth,
                           "octree maximum depth, 1..12 (default: chosen from the scene)")
            ->check(CLI::Range(1, 12));
        command.add_option("--octree-min-prims", common.accel_options.octree.min_primitives,
                           "octree: a node with this many triangles or fewer is a leaf (default 1)");
        // The study put a triangle in every child its bounding box overlaps; ours tests the
        // triangle itself. Kept selectable to measure the references that saves.
        command
            .add_option_function<std::string>(
                "--octree-overlap",
                [&common](const std::string& rule) {
                    common.accel_options.octree.overlap =
                        rule == "box" ? OctreeOverlap::bounding_box : OctreeOverlap::triangle;
                },
                "octree: children a triangle goes to, those it overlaps (triangle, default) or those its "
                "bounding box overlaps (box, the study's rule)")
            ->check(CLI::IsMember({"triangle", "box"}));
        // The full sweep build is the quality reference the binned build's SAH cost is held to.
        command
            .add_option_function<std::string>(
                "--bvh-builder",
                [&common](const std::string& builder) { common.accel_options.bvh.builder = parse_bvh_builder(builder); },
                "BVH: auto (default: spatial splits where the mesh has large triangles and they lower the SAH, "
                "binned elsewhere; bvh2 always binned), binned (SAH over centroid bins), sweep (over every centroid "
                "plane, slow, the quality reference) or spatial (with spatial splits: the higher-quality build, up "
                "to 1.5 references a triangle)")
            ->check(CLI::IsMember(bvh_builder_names()));
        // Havran's perfect splits, off by default: kept selectable to measure what clipping buys.
        command.add_flag("--kd-perfect-splits", common.accel_options.kdtree.perfect_splits,
                         "KD-tree: clip triangles straddling a split plane to each child's cell (Havran)");
        // pbrt's depth limit ends every tree on the study's scenes; selectable to measure what
        // other limits give (bench/experiments/kdtree.md, the kd-depth sweep).
        command
            .add_option("--kd-depth-offset", common.accel_options.kdtree.depth_offset,
                        "KD-tree: levels added to the depth limit round(8 + 1.3 log2 N) (default 0, the study's)")
            ->check(CLI::Range(1 - kKdMaxDepth, kKdMaxDepth - 1));
    }
    command.add_option("--threads", common.threads, "worker threads (0: all cores)")->check(CLI::Range(0, 4096));
}

int run_render(const CommonOptions& common, const RenderOptions& options) {
    const AccelKind kind = accel_kind_or_throw(common.accel);
    const TriangleTest test = triangle_test_or_throw(common.triangle_test);
    const SimdWidth width = simd_width_or_throw(options.simd);
    const SlabTest slabs = slab_test_or_throw(options.slabs);
    const auto mode = parse_render_mode(options.mode);
    if (!mode)
        throw std::invalid_argument(fmt::format("--mode {}: expected shaded, normal, depth, heat or ao", options.mode));
    const auto heat = parse_heat_measure(options.heat);
    if (!heat) throw std::invalid_argument(fmt::format("--heat {}: expected nodes or triangles", options.heat));
    if (options.ao_samples < 1 || options.ao_samples > 1024)
        throw std::invalid_argument(fmt::format("--ao-samples {}: expected 1..1024", options.ao_samples));
    if (options.width == 0 || options.height == 0 || options.width > kMaxImageSide || options.height > kMaxImageSide)
        throw std::invalid_argument(fmt::format("--width/--height {}x{}: each must lie in 1..{}", options.width,
                                                options.height, kMaxImageSide));

    const LoadedScene loaded = load_scene(common.scene, common.manifest);
    const Scene& scene = loaded.scene;
    RenderRequest request;
    request.mode = *mode;
    request.accel = kind;
    request.width = width;
    request.ao_samples = options.ao_samples;
    request.heat = *heat;
    const RenderPlan plan = make_render_plan(scene, request);
    if (options.explain) {  // the plan only: nothing is built or traced
        fmt::print("{}: {} triangles, --mode {}, --accel {}: render plan\n", scene.name, scene.mesh.triangle_count(),
                   to_string(*mode), to_string(kind));
        for (const std::string& line : plan.explanation) fmt::print("  {}\n", line);
        return 0;
    }
    const AnyAccel accel = build_and_warn(kind, scene.mesh, common.accel_options);
    const Camera camera(scene.camera, options.width, options.height);

    const auto trace_start = std::chrono::steady_clock::now();
    const std::vector<Hit> hits = trace_primary(accel, camera, test, width, slabs);
    const double trace_ms = ms_since(trace_start);

    // Shading traces the rays its mode needs beyond the primary ones (shadow rays, ambient occlusion
    // rays, the heat map's counting pass) and is timed on its own, so a shaded render's cost is not
    // hidden behind the primary trace's.
    const auto shade_start = std::chrono::steady_clock::now();
    Image image;
    switch (*mode) {
        case RenderMode::shaded: image = shade_shaded(scene, accel, camera, hits, plan); break;
        case RenderMode::normal: image = shade_normal(scene, camera, hits, plan); break;
        case RenderMode::depth: image = shade_depth(camera, hits); break;
        case RenderMode::heat: image = shade_heat(camera, count_primary_rays(accel, camera, width, test), plan.heat); break;
        case RenderMode::ao: image = shade_ao(scene, accel, camera, hits, plan); break;
    }
    const double shade_ms = ms_since(shade_start);
    write_png(options.output, image);
    if (options.dump_hits) write_hit_buffer(*options.dump_hits, make_hit_buffer(camera.width(), camera.height(), hits));

    const double rays = double(camera.width()) * camera.height();
    fmt::print(
        "{}: {} triangles, load {:.1f} ms, {} build {:.1f} ms, primary trace {:.1f} ms ({:.2f} Mrays/s, {}, "
        "{}, {} threads), shading {:.1f} ms (with its shadow, AO or counting rays), {}x{} {} -> {}\n",
        scene.name, scene.mesh.triangle_count(), loaded.load_ms, to_string(kind), accel.stats().build_ms, trace_ms,
        rays / trace_ms / 1000.0,
        width == SimdWidth::scalar ? std::string("scalar") : fmt::format("simd{}", lane_count(width)), to_string(test),
        tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism), shade_ms, camera.width(),
        camera.height(), to_string(*mode), options.output.string());
    return 0;
}

int run_info(const CommonOptions& common, bool accel_given) {
    const LoadedScene loaded = load_scene(common.scene, common.manifest);
    const Scene& scene = loaded.scene;
    const Aabb bounds = scene.mesh.bounds();
    fmt::print("{}: {} triangles, {} vertices, normals {}, bounds [{} {} {}]..[{} {} {}], light {}, load {:.1f} ms ({})\n",
               scene.name, scene.mesh.triangle_count(), scene.mesh.vertex_count(), scene.mesh.has_normals() ? "yes" : "no",
               bounds.lo.x, bounds.lo.y, bounds.lo.z, bounds.hi.x, bounds.hi.y, bounds.hi.z,
               scene.light ? "yes" : "no", loaded.load_ms, loaded.source);
    if (accel_given)
        fmt::print("{}\n", build_and_warn(accel_kind_or_throw(common.accel), scene.mesh, common.accel_options).stats().to_line());
    return 0;
}

/// The CPU, the kernels built in, what TRIDENT_ISA allows, and the width --simd auto picks.
int run_cpu() {
    const auto cap = isa_cap();  // a bad TRIDENT_ISA is an error before anything is printed
    fmt::print("cpu:       {}\n", cpu_model());
    std::string features;
    for (const std::string& feature : cpu_features()) features += (features.empty() ? "" : " ") + feature;
    fmt::print("features:  {}\n", features.empty() ? "none of sse4.2 and above" : features);
    fmt::print("baseline:  -march={}\n", baseline_march());
    fmt::print("cap:       {}\n", cap ? fmt::format("TRIDENT_ISA={}", to_string(*cap)) : std::string("none (TRIDENT_ISA unset)"));
    for (const SimdWidth width : {SimdWidth::w4, SimdWidth::w8, SimdWidth::w16}) {
        const char* march = kernel_march(width);
        const char* state = !is_compiled_in(width) ? "not built"
                            : !cpu_supports(width)  ? "built, this CPU lacks it"
                            : !cap_allows(width)    ? "built, capped by TRIDENT_ISA"
                                                    : "runs here";
        fmt::print("{:>2} lanes:  {}{}\n", to_string(width), state, march ? fmt::format(" (-march={})", march) : "");
    }
    fmt::print("--simd auto: {}\n", to_string(widest_supported()));
    return 0;
}

int run_scenes(const std::optional<std::filesystem::path>& manifest) {
    fmt::print("built-in scenes:\n");
    for (const BuiltinSceneInfo& info : builtin_scenes())
        fmt::print("  {:<10} {:>9} triangles{}  {}\n", info.name, info.triangles, info.closed ? " (closed)" : "         ",
                   info.description);
    if (manifest) {
        fmt::print("{}:\n", manifest->string());
        for (const ManifestEntry& entry : load_manifest(*manifest))
            fmt::print("  {:<10} {:>9} triangles  {}\n", entry.name, entry.expected_triangles, entry.file.string());
    }
    return 0;
}

}  // namespace
}  // namespace trident

int main(int argc, char** argv) {
    using namespace trident;
    CLI::App app{"trident: build, trace and compare BVH, KD-tree and Octree"};
    app.require_subcommand(1);

    CommonOptions common;
    RenderOptions render;
    CLI::App* render_cmd = app.add_subcommand("render", "render a scene to a PNG (and optionally a hit buffer)");
    add_common_options(*render_cmd, common, true);
    render_cmd->add_option("--simd", render.simd, "traversal width: auto|scalar|4|8|16");
    render_cmd->add_option("--slabs", render.slabs, "box tests of the primary rays: robust (default) or fast");
    render_cmd->add_option("--width", render.width, "image width in pixels");
    render_cmd->add_option("--height", render.height, "image height in pixels");
    render_cmd->add_option("--mode", render.mode, "shaded|normal|depth|heat|ao");
    render_cmd->add_option("--ao-samples", render.ao_samples, "ambient-occlusion rays per pixel with --mode ao (default 16)");
    render_cmd->add_option("--heat", render.heat, "what --mode heat counts per pixel: nodes (default) or triangles");
    render_cmd->add_flag("--explain", render.explain, "print the render plan (passes and why) and exit without rendering");
    render_cmd->add_option("--output", render.output, "PNG file to write");
    render_cmd->add_option("--dump-hits", render.dump_hits, "write the hit buffer of BENCHMARK.md to this file");

    CommonOptions info_common;
    CLI::App* info_cmd = app.add_subcommand("info", "scene statistics, and a structure's statistics with --accel");
    add_common_options(*info_cmd, info_common, true);

    std::optional<std::filesystem::path> scenes_manifest;
    CLI::App* scenes_cmd = app.add_subcommand("scenes", "list the built-in scenes (and a manifest's)");
    scenes_cmd->add_option("--scenes", scenes_manifest, "also list the scenes of this manifest");
    const StressCommand stress_cmd(app);
    CLI::App* cpu_cmd = app.add_subcommand(
        "cpu", "the CPU's model and instruction sets, the packet kernels built in and the ones a run chooses");

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "trident: %s\n", e.what());
        return 2;
    }

    try {
        const CommonOptions& chosen = render_cmd->parsed() ? common : info_common;
        const std::size_t threads =
            chosen.threads > 0 ? std::size_t(chosen.threads) : std::size_t(tbb::info::default_concurrency());
        tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, threads);
        if (render_cmd->parsed()) return run_render(common, render);
        if (info_cmd->parsed()) return run_info(info_common, info_cmd->count("--accel") > 0);
        if (stress_cmd.parsed()) return stress_cmd.run();
        if (cpu_cmd->parsed()) return run_cpu();
        return run_scenes(scenes_manifest);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "trident: %s\n", e.what());
        return 1;
    }
}
