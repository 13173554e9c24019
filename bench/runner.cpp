#include "bench/runner.h"

#include <fmt/format.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <span>

#include "accel/any_accel.h"
#include "bench/embree_baseline.h"
#include "bench/progress.h"
#include "bench/ray_sets.h"
#include "bench/reference.h"
#include "bench/scene_selection.h"
#include "bench/statistics.h"
#include "camera/camera.h"
#include "render/heat_map.h"
#include "render/hit_buffer.h"
#include "render/ray_stream.h"
#include "render/render_plan.h"
#include "render/trace.h"
#include "scene/scene_source.h"
#include "simd/width.h"

namespace trident::bench {
namespace {

struct PerRayCounts {
    double nodes = 0.0, triangles = 0.0;
};

/// Nodes visited and triangles tested per primary ray. count_primary_rays gives every pixel of a
/// packet its packet's count; each pixel here takes its share, 1 / (rays in its packet), so the
/// sum is the packets' total. Blocks are aligned to the image (trace_primary's tiles are multiples
/// of every block), so a pixel's packet is the block around it, cut at the image's edges.
PerRayCounts count_per_ray(const AnyAccel& accel, const Camera& camera, SimdWidth width, TriangleTest test,
                           SlabTest slabs) {
    const std::vector<TraversalCounters> counts = width == SimdWidth::scalar
                                                      ? count_primary(accel, camera, test, slabs)
                                                      : count_primary_rays(accel, camera, width, test);
    const auto [block_w, block_h] = width == SimdWidth::scalar ? std::pair{1u, 1u} : packet_block(lane_count(width));
    const std::uint32_t w = camera.width(), h = camera.height();
    PerRayCounts sum;
    for (std::uint32_t y = 0; y < h; ++y)
        for (std::uint32_t x = 0; x < w; ++x) {
            const std::uint32_t x0 = x - x % block_w, y0 = y - y % block_h;
            const double lanes = double(std::min(block_w, w - x0) * std::min(block_h, h - y0));
            const TraversalCounters& c = counts[std::size_t(y) * w + x];
            sum.nodes += double(c.nodes_visited) / lanes;
            sum.triangles += double(c.triangles_tested) / lanes;
        }
    const double rays = double(w) * double(h);
    return {sum.nodes / rays, sum.triangles / rays};
}

/// One structure with the options it is built with: the defaults, or one value of a sweep.
struct StructureConfig {
    AccelKind kind;
    AccelOptions options;
    std::optional<double> sweep_value;
};

std::vector<StructureConfig> structure_configs(const BenchOptions& options) {
    std::vector<StructureConfig> configs;
    if (options.sweep) {
        for (double value : options.sweep->values) {
            StructureConfig config{options.sweep->structure, {}, value};
            config.options.bvh.width = options.bvh_width;
            config.options.bvh.builder = options.bvh_builder;
            options.sweep->set(config.options, value);
            configs.push_back(config);
        }
        return configs;
    }
    for (AccelKind kind : options.structures) {
        StructureConfig config{kind, {}, std::nullopt};
        config.options.bvh.width = options.bvh_width;
        config.options.bvh.builder = options.bvh_builder;
        configs.push_back(config);
    }
    return configs;
}

/// Triangle test x slab test pairs measured per structure and traversal (issue 8's grid).
std::size_t variant_count(const BenchOptions& options) {
    return options.triangle_tests.size() * options.slab_tests.size();
}

/// Embree's rows, one per packet width and the stream, per ray kind that has them.
std::size_t embree_row_count(const BenchOptions& options) {
    return options.runs_embree() ? options.embree_packet_widths.size() + (options.embree_stream ? 1 : 0) : 0;
}

/// Our Mrays/s over Embree's on the same scene, rays and thread count: scalar rows compare with
/// rtcIntersect1 (rtcOccluded1 for shadow rays), simdN rows with rtcIntersectN (rtcOccludedN).
void fill_ratios_to_embree(std::span<BenchRow> rows) {
    for (BenchRow& row : rows) {
        if (row.is_embree()) continue;
        const auto traversal = parse_traversal(row.traversal);
        if (!traversal) continue;
        const std::string counterpart = embree_counterpart(*traversal, row.ray_kind);
        for (const BenchRow& embree : rows)
            if (embree.is_embree() && embree.threads == row.threads && embree.traversal == counterpart &&
                embree.ray_kind == row.ray_kind && embree.mrays_per_s() > 0)
                row.ratio_to_embree = row.mrays_per_s() / embree.mrays_per_s();
    }
}

class BenchmarkRun {
public:
    explicit BenchmarkRun(const BenchOptions& options)
        : options_(options),
          configs_(structure_configs(options)),
          scenes_(select_scenes(options)),
          progress_(
              scenes_.size() * options.threads.size() *
                  (embree_row_count(options) + configs_.size() * options.traversals.size() * variant_count(options)),
              options.quiet) {}

    BenchReport run() {
        start_report();
        for (const SceneChoice& choice : scenes_) run_scene(choice);
        if (configs_.empty())
            report_.notes.push_back("no structure but the brute force is built yet: pass --accel brute to measure it");
        return std::move(report_);
    }

private:
    void start_report() {
        report_.machine = describe_machine();
        report_.command_line = options_.command_line;
        report_.width = options_.width;
        report_.height = options_.height;
        report_.repeats = options_.repeats;
        report_.threads = options_.threads;
        if (std::find(options_.structures.begin(), options_.structures.end(), AccelKind::bvh) != options_.structures.end())
            report_.notes.push_back(fmt::format("bvh rows: the wide BVH, {} children a node, blocks of 4 triangles; "
                                                "bvh2 rows: the binary BVH",
                                                options_.bvh_width));
        // The brute force has no boxes to cull by (TileCuller): the note is for the others.
        const bool culls_tiles = options_.tile_culling == TileCulling::frustum &&
                                 std::find(options_.ray_kinds.begin(), options_.ray_kinds.end(), RayKind::primary) !=
                                     options_.ray_kinds.end() &&
                                 std::any_of(options_.structures.begin(), options_.structures.end(),
                                             [](AccelKind kind) { return kind != AccelKind::brute; });
        if (culls_tiles)
            report_.notes.push_back(
                "primary rows of ours: a 16x16 tile none of whose rays can reach the structure's top boxes gets "
                "misses without being traced (--tile-culling frustum; Embree's rows trace every ray)");
        if (options_.bvh_builder != BvhOptions{}.builder)
            report_.notes.push_back(fmt::format("bvh and bvh2 rows: built with {}", to_string(options_.bvh_builder)));
        for (TriangleTest test : options_.triangle_tests)
            report_.triangle_test += fmt::format("{}{}", report_.triangle_test.empty() ? "" : ", ", to_string(test));
        for (SlabTest slabs : options_.slab_tests)
            report_.slabs += fmt::format("{}{}", report_.slabs.empty() ? "" : ", ", to_string(slabs));
        report_.reference = describe_reference(options_.reference);
        if (const std::optional<IsaLevel> cap = trident::isa_cap()) report_.isa_cap = to_string(*cap);
#if TRIDENT_HAVE_EMBREE
        if (options_.runs_embree() || options_.pairs_with(PairPartner::embree))
            report_.embree_settings = embree_settings(options_.embree_quality, options_.embree_isa);
        report_.embree_isa = to_string(options_.embree_isa);
#endif
        if (options_.sweep) {
            report_.sweep_name = options_.sweep->name;
            report_.sweep_parameter = options_.sweep->parameter;
        }
        if (options_.dump_hits) std::filesystem::create_directories(*options_.dump_hits);
    }

    void run_scene(const SceneChoice& choice) {
        progress_.show(fmt::format("{}: loading", choice.spec));
        const LoadedScene loaded = load_scene(choice.spec, choice.manifest);
        const Camera camera(loaded.scene.camera, options_.width, options_.height);
        progress_.show(fmt::format("{}: tracing the reference", loaded.scene.name));
        const ReferenceTrace reference = make_reference(options_.reference, loaded.scene, camera);
        if (reference.description != report_.reference)
            report_.notes.push_back(fmt::format("{}: reference {}", loaded.scene.name, reference.description));
        hits_.assign(std::size_t(camera.width()) * camera.height(), Hit{});
        if (asks(RayKind::shadow) || asks(RayKind::diffuse)) {
            progress_.show(fmt::format("{}: making shadow and diffuse rays", loaded.scene.name));
            ray_sets_ = make_scene_ray_sets(loaded.scene, camera, options_.ray_kinds);
            report_.notes.insert(report_.notes.end(), ray_sets_.notes.begin(), ray_sets_.notes.end());
        }

        partner_hits_.assign(hits_.size(), Hit{});
        // --paired bvh: one BVH of the default options per scene for the other structures' rows.
        // Partners time primary rays only, so a run without them builds none.
        std::optional<AnyAccel> bvh_partner;
        if (asks(RayKind::primary) && options_.pairs_with(PairPartner::bvh) &&
            std::any_of(configs_.begin(), configs_.end(),
                        [](const StructureConfig& c) { return c.kind != AccelKind::bvh; })) {
            progress_.show(fmt::format("{}: building the BVH to pair with", loaded.scene.name));
            bvh_partner.emplace(AnyAccel::build(AccelKind::bvh, loaded.scene.mesh, AccelOptions{}));
        }

        const std::size_t first_row = report_.rows.size();
        for (int threads : options_.threads) {
            const tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
            SceneRun run{loaded, camera, reference, threads, bvh_partner ? &*bvh_partner : nullptr};
#if TRIDENT_HAVE_EMBREE
            // --paired embree: Embree's scene on a device of this row's thread count, as its own rows.
            std::optional<EmbreeDevice> embree_device;
            std::optional<EmbreeScene> embree_partner;
            if (options_.pairs_with(PairPartner::embree)) {
                progress_.show(fmt::format("{}: building Embree's scene to pair with", loaded.scene.name));
                embree_device.emplace(threads, options_.embree_isa);
                embree_partner.emplace(*embree_device, loaded.scene.mesh, options_.embree_quality);
                run.embree_partner = &*embree_partner;
            }
#endif
            if (options_.runs_embree()) run_embree(run);
            for (const StructureConfig& config : configs_) run_structure(run, config);
        }
        fill_ratios_to_embree(std::span(report_.rows).subspan(first_row));
    }

    struct SceneRun {
        const LoadedScene& loaded;
        const Camera& camera;
        const ReferenceTrace& reference;
        int threads;
        const AnyAccel* bvh_partner = nullptr;  // --paired bvh
#if TRIDENT_HAVE_EMBREE
        const EmbreeScene* embree_partner = nullptr;  // --paired embree
#endif
    };

    BenchRow start_row(const SceneRun& run, std::string structure, std::string traversal) const {
        BenchRow row;
        row.scene = run.loaded.scene.name;
        row.scene_source = run.loaded.source;
        row.triangles = run.loaded.scene.mesh.triangle_count();
        row.load_ms = run.loaded.load_ms;
        row.structure = std::move(structure);
        row.traversal = std::move(traversal);
        row.threads = run.threads;
        row.width = options_.width;
        row.height = options_.height;
        row.repeats = options_.repeats;
        row.reference = run.reference.description;
        return row;
    }

    std::string run_label(int run) const {
        return run < kWarmupRuns ? std::string("warm-up")
                                 : fmt::format("{}/{}", run - kWarmupRuns + 1, options_.repeats);
    }

    /// A trace timed right after each of a row's renders, on the same rays; the median of its time
    /// over the render's goes into the row's field `ratio`. A partner of several traces ("Embree's
    /// best") times each of them and takes the fastest, run by run.
    struct Partner {
        std::vector<std::function<void()>> traces;
        std::optional<double> BenchRow::*ratio;
    };

    /// Times the row's renders into row.render_ms. With --scaling, a row at more than one thread
    /// also times each render again on one thread right after it, into
    /// row.speedup_over_one_thread: the two times of a pair are seconds apart, so they drift
    /// together on a shared machine, where the rows at one thread ran minutes earlier. Each of
    /// `partners` (--vs-single, --paired) is timed the same way after each render.
    template <class TraceOnce>
    void time_renders(const std::string& what, BenchRow& row, TraceOnce&& trace_once,
                      std::span<const Partner> partners = {}) {
        auto timed = [](auto&& trace) {
            const auto start = std::chrono::steady_clock::now();
            trace();
            return ms_since(start);
        };
        const bool paired = options_.scaling && row.threads > 1;
        std::vector<double> speedups;
        std::vector<std::vector<double>> partner_ratios(partners.size());
        row.render_ms = measure_repeated(options_.repeats, [&](int run) {
            progress_.show(fmt::format("{}: render {}", what, run_label(run)));
            const double ms = timed(trace_once);
            if (paired) {
                // The most restrictive of nested limits applies: one thread until this one ends.
                const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
                const double one_thread_ms = timed(trace_once);
                if (run >= kWarmupRuns) speedups.push_back(one_thread_ms / ms);
            }
            for (std::size_t i = 0; i < partners.size(); ++i) {
                double partner_ms = std::numeric_limits<double>::infinity();
                for (const auto& trace : partners[i].traces) partner_ms = std::min(partner_ms, timed(trace));
                if (run >= kWarmupRuns) partner_ratios[i].push_back(partner_ms / ms);
            }
            return ms;
        });
        if (paired) row.speedup_over_one_thread = summarize(std::move(speedups)).median;
        for (std::size_t i = 0; i < partners.size(); ++i)
            row.*partners[i].ratio = summarize(std::move(partner_ratios[i])).median;
    }

    /// The error against the reference, the hit buffer dump, and the row into the report.
    void finish_row(const SceneRun& run, BenchRow row, const std::string& dump_name) {
        const HitBuffer hits = make_hit_buffer(run.camera.width(), run.camera.height(), hits_);
        row.error = error_against(run.reference, hits);
        if (options_.dump_hits && run.threads == options_.threads.front())
            write_hit_buffer(*options_.dump_hits / fmt::format("{}.{}.hits", row.scene, dump_name), hits);
        report_.rows.push_back(std::move(row));
        progress_.configuration_done();
    }

    void run_embree([[maybe_unused]] const SceneRun& run) {
#if TRIDENT_HAVE_EMBREE
        const std::string what = fmt::format("{}: embree, {} threads", run.loaded.scene.name, run.threads);
        const EmbreeDevice device(run.threads, options_.embree_isa);
        std::optional<EmbreeScene> scene;
        const Summary build = measure_repeated(options_.repeats, [&](int i) {
            progress_.show(fmt::format("{}: build {}", what, run_label(i)));
            scene.reset();
            scene.emplace(device, run.loaded.scene.mesh, options_.embree_quality);
            return scene->build_ms();
        });
        for (int width : options_.embree_packet_widths) {
            if (!asks(RayKind::primary)) break;
            BenchRow row = start_row(run, kEmbreeStructure, embree_call_name(width));
            row.build_ms = build;
            time_renders(fmt::format("{} {}", what, row.traversal), row,
                         [&] { scene->trace(run.camera, width, hits_); });
            row.bytes = scene->bytes();
            row.note = embree_settings(options_.embree_quality, options_.embree_isa);
            finish_row(run, std::move(row), fmt::format("embree.{}", embree_call_name(width)));
        }
        if (asks(RayKind::primary) && options_.embree_stream) {  // its stream: rtcIntersect1M on 8x8 blocks
            BenchRow row = start_row(run, kEmbreeStructure, kEmbreeStreamName);
            row.build_ms = build;
            time_renders(fmt::format("{} {}", what, row.traversal), row,
                         [&] { scene->trace_stream(run.camera, hits_); });
            row.bytes = scene->bytes();
            row.note = embree_settings(options_.embree_quality, options_.embree_isa);
            finish_row(run, std::move(row), fmt::format("embree.{}", kEmbreeStreamName));
        }
        for (int width : options_.embree_packet_widths) {  // shadow rays: rtcOccluded1 / 4 / 8 / 16
            if (!asks(RayKind::shadow)) break;
            BenchRow row = start_row(run, kEmbreeStructure, embree_occluded_name(width));
            row.build_ms = build;
            occluded_.resize(ray_sets_.shadow.rays.size());
            time_renders(fmt::format("{} {} shadow", what, row.traversal), row,
                         [&] { scene->occluded(ray_sets_.shadow.rays, width, PacketGrouping::in_order, occluded_); });
            finish_secondary_row(std::move(row), RayKind::shadow, scene->bytes());
        }
        for (int width : options_.embree_packet_widths) {  // diffuse rays: rtcIntersect1 / 4 / 8 / 16
            if (!asks(RayKind::diffuse)) break;
            BenchRow row = start_row(run, kEmbreeStructure, embree_call_name(width));
            row.build_ms = build;
            secondary_hits_.resize(ray_sets_.diffuse.rays.size());
            time_renders(fmt::format("{} {} diffuse", what, row.traversal), row, [&] {
                scene->intersect(ray_sets_.diffuse.rays, width, PacketGrouping::by_octant, secondary_hits_);
            });
            finish_secondary_row(std::move(row), RayKind::diffuse, scene->bytes());
        }
#endif
    }

    bool asks(RayKind kind) const {
        return std::find(options_.ray_kinds.begin(), options_.ray_kinds.end(), kind) != options_.ray_kinds.end();
    }

    /// A shadow or diffuse row: Mrays/s over the rays traced; no hit-buffer error (the error
    /// columns are about primary rays). Not counted in the progress total.
    void finish_secondary_row(BenchRow row, RayKind kind, std::optional<std::size_t> bytes) {
        row.ray_kind = to_string(kind);
        if (!row.is_embree()) {  // our secondary rays use the default tests
            row.triangle_test = to_string(TriangleTest::watertight);
            row.slabs = to_string(SlabTest::robust);
        }
        row.ray_count = kind == RayKind::shadow ? ray_sets_.shadow_traced : ray_sets_.diffuse_traced;
        row.bytes = bytes;
        row.reference.clear();
        if (row.is_embree())
            row.note = embree_settings(options_.embree_quality, options_.embree_isa) +
                       (kind == RayKind::diffuse && row.traversal != embree_call_name(1)
                            ? fmt::format("; packets {}", to_string(PacketGrouping::by_octant))
                            : "");
        report_.rows.push_back(std::move(row));
    }

    /// Our shadow (AnyHit) or diffuse row for one structure and traversal (default triangle and
    /// slab tests): shadow rays as packets in primary-packet order, diffuse rays as packets grouped
    /// by direction octant, each row at its own width (the renderer's pick for diffuse rays is
    /// incoherent_traversal()). Partners trace into their own buffers (partner_occluded_,
    /// partner_secondary_hits_), so the row's results stay as the row traced them.
    template <bool AnyHit>
    void run_secondary_row(const SceneRun& run, const StructureConfig& config, const AnyAccel& accel,
                           const Summary& build, Traversal traversal, const std::string& what) {
        const RayKind kind = AnyHit ? RayKind::shadow : RayKind::diffuse;
        const std::vector<Ray>& rays = AnyHit ? ray_sets_.shadow.rays : ray_sets_.diffuse.rays;
        auto& results = [&]() -> auto& {
            if constexpr (AnyHit)
                return occluded_;
            else
                return secondary_hits_;
        }
        ();
        auto& partner_results = [&]() -> auto& {
            if constexpr (AnyHit)
                return partner_occluded_;
            else
                return partner_secondary_hits_;
        }
        ();
        results.resize(rays.size());
        partner_results.resize(rays.size());
        partner_secondary_hits_.resize(rays.size());  // --paired closest
        auto trace = [&](auto& into, StreamTraversal stream) {
            if constexpr (AnyHit)
                occlude_stream_parallel(accel, rays, into, stream);
            else
                intersect_stream_parallel(accel, rays, into, stream);
        };

        BenchRow row = start_row(run, to_string(config.kind), to_string(traversal));
        row.builder = accel.stats().builder;
        row.build_ms = build;
        const SimdWidth width = simd_width(traversal);
        // Diffuse rays are incoherent, as Embree's rtcIntersect1 takes them by default.
        const RayCoherence coherence = AnyHit ? RayCoherence::coherent : RayCoherence::incoherent;
        const StreamTraversal stream{width, AnyHit ? PacketGrouping::in_order : PacketGrouping::by_octant,
                                     SlabTest::robust, coherence, options_.last_occluder};
        if (stream_walks_rays_alone(accel, stream))
            row.note = "incoherent rays over a large tree: every lane alone from the root, packets not cut";
        else if (!AnyHit && width != SimdWidth::scalar)
            row.note = fmt::format("packets {}", to_string(stream.grouping));
        if (AnyHit && !options_.last_occluder) row.note = "last occluder off";
        std::vector<Partner> partners;
        if (options_.vs_single && width != SimdWidth::scalar)
            partners.push_back(
                {{[&] { trace(partner_results, {.coherence = coherence, .last_occluder = options_.last_occluder}); }},
                 &BenchRow::speedup_over_single_rays});
        if (AnyHit && options_.pairs_with(PairPartner::closest))
            partners.push_back({{[&] { intersect_stream_parallel(accel, rays, partner_secondary_hits_, stream); }},
                                &BenchRow::paired_over_closest});
#if TRIDENT_HAVE_EMBREE
        if (run.embree_partner)
            partners.push_back({{[&] {
                                    if constexpr (AnyHit)
                                        run.embree_partner->occluded(rays, rays_per_call(traversal), stream.grouping,
                                                                     partner_results);
                                    else
                                        run.embree_partner->intersect(rays, rays_per_call(traversal), stream.grouping,
                                                                      partner_results);
                                }},
                                &BenchRow::paired_over_embree});
#endif
        time_renders(
            fmt::format("{} {} {}", what, row.traversal, to_string(kind)), row, [&] { trace(results, stream); },
            partners);
        finish_secondary_row(std::move(row), kind, accel.stats().bytes);
    }

    void run_structure(const SceneRun& run, const StructureConfig& config) {
        const std::string& scene_name = run.loaded.scene.name;
        if (config.kind == AccelKind::brute && run.loaded.scene.mesh.triangle_count() > kBruteMaxTriangles) {
            if (run.threads == options_.threads.front())
                report_.notes.push_back(fmt::format(
                    "brute refused on {}: {} triangles is over {} (W x H x N triangle tests would take hours)",
                    scene_name, run.loaded.scene.mesh.triangle_count(), kBruteMaxTriangles));
            for (std::size_t i = 0; i < options_.traversals.size() * variant_count(options_); ++i)
                progress_.configuration_done();
            return;
        }
        std::string label = to_string(config.kind);
        if (config.sweep_value) label += fmt::format(".{}={:g}", options_.sweep->name, *config.sweep_value);
        const std::string what = fmt::format("{}: {}, {} threads", scene_name, label, run.threads);

        std::optional<AnyAccel> accel;
        const Summary build = measure_repeated(options_.repeats, [&](int i) {
            progress_.show(fmt::format("{}: build {}", what, run_label(i)));
            accel.reset();  // free the previous build first: one structure in memory at a time
            accel.emplace(AnyAccel::build(config.kind, run.loaded.scene.mesh, config.options));
            return accel->stats().build_ms;
        });
        for (Traversal traversal : options_.traversals) {
            if (!has_packet_traversal(*accel, simd_width(traversal))) {
                skip_traversal(run, config.kind, traversal);
                continue;
            }
            if (asks(RayKind::primary))
                for (TriangleTest test : options_.triangle_tests)
                    for (SlabTest slabs : options_.slab_tests)
                        run_variant(run, config, *accel, build, traversal, test, slabs, what, label);
            if (asks(RayKind::shadow)) run_secondary_row<true>(run, config, *accel, build, traversal, what);
            if (asks(RayKind::diffuse)) run_secondary_row<false>(run, config, *accel, build, traversal, what);
        }
    }

    /// One row: the structure traced at one traversal width with one triangle test and slab test.
    void run_variant(const SceneRun& run, const StructureConfig& config, const AnyAccel& accel, const Summary& build,
                     Traversal traversal, TriangleTest test, SlabTest slabs, const std::string& what_structure,
                     const std::string& label) {
        const AccelStats& stats = accel.stats();
        BenchRow row = start_row(run, to_string(config.kind), to_string(traversal));
        row.builder = stats.builder;
        row.triangle_test = to_string(test);
        row.slabs = to_string(slabs);
        // The default variant keeps the plain labels (and hit-dump file names).
        const bool default_variant = test == TriangleTest::watertight && slabs == SlabTest::robust;
        const std::string variant = default_variant ? "" : fmt::format(".{}.{}", to_string(test), to_string(slabs));
        const std::string what =
            default_variant ? what_structure
                            : fmt::format("{} ({}, {} slabs)", what_structure, to_string(test), to_string(slabs));
        row.build_ms = build;
        // --paired: the partners trace into their own buffer, so the row's hits stay for its error.
        std::vector<Partner> partners;
        if (options_.pairs_with(PairPartner::scalar) && traversal != Traversal::scalar)
            partners.push_back({{[&] {
                                    trace_primary(accel, run.camera, partner_hits_, test, SimdWidth::scalar, slabs,
                                                  options_.tile_culling);
                                }},
                                &BenchRow::paired_over_scalar});
        if (run.bvh_partner && config.kind != AccelKind::bvh)
            partners.push_back({{[&] {
                                    trace_primary(*run.bvh_partner, run.camera, partner_hits_, test,
                                                  simd_width(traversal), slabs, options_.tile_culling);
                                }},
                                &BenchRow::paired_over_bvh});
#if TRIDENT_HAVE_EMBREE
        if (run.embree_partner) {
            const EmbreeScene& embree = *run.embree_partner;
            partners.push_back({{[&] { embree.trace(run.camera, rays_per_call(traversal), partner_hits_); }},
                                &BenchRow::paired_over_embree});
            // Embree's best on primary rays: the faster of its 16-wide packets and its stream.
            partners.push_back({{[&] { embree.trace(run.camera, 16, partner_hits_); },
                                 [&] { embree.trace_stream(run.camera, partner_hits_); }},
                                &BenchRow::paired_over_embree_best});
        }
#endif
        time_renders(
            fmt::format("{} {}", what, row.traversal), row,
            [&] { trace_primary(accel, run.camera, hits_, test, simd_width(traversal), slabs, options_.tile_culling); },
            partners);
        row.nodes = stats.nodes;
        row.leaves = stats.leaves;
        row.max_depth = stats.max_depth;
        row.sah_cost = stats.sah_cost;
        row.bytes = stats.bytes;
        // A separate counting pass. Packet rows count a node (or triangle) once per packet that
        // visits it, divided among the packet's rays; the packet counting pass has the robust
        // slab test only, so packet rows with fast slabs leave the counts empty.
        if (traversal == Traversal::scalar || slabs == SlabTest::robust) {
            progress_.show(fmt::format("{} {}: counting", what, row.traversal));
            const PerRayCounts counts = count_per_ray(accel, run.camera, simd_width(traversal), test, slabs);
            row.nodes_per_ray = counts.nodes;
            row.triangles_per_ray = counts.triangles;
        }
        if (config.sweep_value) {
            row.sweep_parameter = options_.sweep->parameter;
            row.sweep_value = config.sweep_value;
        }
        finish_row(run, std::move(row), fmt::format("{}.{}{}", label, to_string(traversal), variant));
    }

    /// A structure without a packet traversal of that width yet: named once in the notes.
    void skip_traversal(const SceneRun& run, AccelKind kind, Traversal traversal) {
        const std::string note = fmt::format("{} {}: no packet traversal of that width yet, not measured",
                                             to_string(kind), to_string(traversal));
        if (run.threads == options_.threads.front() &&
            std::find(report_.notes.begin(), report_.notes.end(), note) == report_.notes.end())
            report_.notes.push_back(note);
        for (std::size_t i = 0; i < variant_count(options_); ++i) progress_.configuration_done();
    }

    const BenchOptions& options_;
    std::vector<StructureConfig> configs_;
    std::vector<SceneChoice> scenes_;
    Progress progress_;
    BenchReport report_;
    std::vector<Hit> hits_;                       // one image of hits, reused by every trace
    std::vector<Hit> partner_hits_;               // the same for the --paired partners' traces
    SceneRaySets ray_sets_;                       // the scene's shadow and diffuse rays (--rays)
    std::vector<std::uint8_t> occluded_;          // shadow results, reused
    std::vector<Hit> secondary_hits_;             // diffuse results, reused
    std::vector<std::uint8_t> partner_occluded_;  // the same for the partners' traces
    std::vector<Hit> partner_secondary_hits_;
};

}  // namespace

BenchReport run_benchmark(const BenchOptions& options) { return BenchmarkRun(options).run(); }

}  // namespace trident::bench
