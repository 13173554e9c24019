#include "bench/options.h"

#include <fmt/format.h>
#include <tbb/info.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <charconv>
#include <stdexcept>

#include "bench/embree_baseline.h"
#include "bench/statistics.h"
#include "simd/width.h"

namespace trident::bench {
namespace {

/// The options as typed; resolve() checks them and turns them into BenchOptions.
struct Arguments {
    std::vector<std::string> scenes, only, accel, simd, threads, embree, triangle_tests, slabs;
    std::optional<std::string> embree_quality, embree_isa;
    std::vector<std::string> rays, paired;
    std::optional<std::filesystem::path> manifest, reference_hits, dump_hits, csv, json, markdown;
    std::optional<std::string> sweep;
    std::string reference = "auto";
    long long width = 1920, height = 1080, repeats = kRecommendedRepeats;
    int bvh_width = BvhOptions{}.width;
    std::string bvh_builder = "auto";
    bool quiet = false, scaling = false, vs_single = false;
    std::string last_occluder = "on";
    std::string tile_culling = "frustum";
};

[[noreturn]] void refuse(const std::string& message) { throw std::invalid_argument(message); }

std::optional<int> parse_int(std::string_view text) {
    int value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc{} || end != text.data() + text.size()) return std::nullopt;
    return value;
}

template <class T>
void push_unique(std::vector<T>& list, const T& value) {
    if (std::find(list.begin(), list.end(), value) == list.end()) list.push_back(value);
}

std::string quoted_command_line(int argc, char** argv) {
    std::string line;
    for (int i = 0; i < argc; ++i) {
        const std::string arg = argv[i];
        if (i) line += ' ';
        line += arg.find_first_of(" \t\"'") == std::string::npos ? arg : fmt::format("'{}'", arg);
    }
    return line;
}

std::vector<AccelKind> resolve_structures(const std::vector<std::string>& names) {
    std::vector<AccelKind> kinds;
    if (names.empty()) {  // every structure built, except the brute force, which must be asked for
        for (AccelKind kind : built_accel_kinds())
            if (kind != AccelKind::brute) kinds.push_back(kind);
        return kinds;
    }
    for (const std::string& name : names) {
        const auto kind = parse_accel_kind(name);
        if (!kind) refuse(fmt::format("--accel {}: unknown structure (brute, bvh, bvh2, kdtree, octree)", name));
        push_unique(kinds, *kind);
    }
    return kinds;
}

std::vector<Traversal> resolve_traversals(const std::vector<std::string>& names) {
    std::vector<Traversal> traversals;
    for (const std::string& name : names) {
        const auto traversal = parse_traversal(name);
        if (!traversal) refuse(fmt::format("--simd {}: expected scalar, simd4, simd8 or simd16", name));
        if (!is_runnable(*traversal))
            refuse(fmt::format("--simd {}: not runnable here (needs {} kernels in this binary and on this CPU)", name,
                               instruction_set(*traversal)));
        push_unique(traversals, *traversal);
    }
    if (traversals.empty()) traversals.push_back(Traversal::scalar);
    return traversals;
}

std::vector<TriangleTest> resolve_triangle_tests(const std::vector<std::string>& names) {
    std::vector<TriangleTest> tests;
    for (const std::string& name : names) {
        if (const auto test = parse_triangle_test(name))
            push_unique(tests, *test);
        else
            refuse(fmt::format("--triangle-test {}: expected watertight or moller_trumbore", name));
    }
    if (tests.empty()) tests.push_back(TriangleTest::watertight);
    return tests;
}

std::vector<SlabTest> resolve_slab_tests(const std::vector<std::string>& names) {
    std::vector<SlabTest> slabs;
    for (const std::string& name : names) {
        if (const auto slabs_choice = parse_slab_test(name))
            push_unique(slabs, *slabs_choice);
        else
            refuse(fmt::format("--slabs {}: expected robust or fast", name));
    }
    if (slabs.empty()) slabs.push_back(SlabTest::robust);
    return slabs;
}

std::vector<int> resolve_threads(const std::vector<std::string>& texts) {
    const int hardware = tbb::info::default_concurrency();
    std::vector<int> threads;
    for (const std::string& text : texts) {
        const auto count = text == "all" ? std::optional<int>(hardware) : parse_int(text);
        if (!count || *count < 1 || *count > hardware)
            refuse(
                fmt::format("--threads {}: each count must lie in 1..{} (this machine's hardware threads) or be 'all'",
                            text, hardware));
        push_unique(threads, *count);
    }
    if (threads.empty()) threads.push_back(hardware);
    return threads;
}

/// --embree's list into the packet widths and the stream row; all of them when not given.
void resolve_embree(const std::vector<std::string>& texts, bool given, BenchOptions& options) {
    if (!given) {
        if (kHaveEmbree) {
            options.embree_packet_widths.assign(std::begin(kEmbreePacketWidths), std::end(kEmbreePacketWidths));
            options.embree_stream = true;
        }
        return;
    }
    if (texts.size() == 1 && texts.front() == "none") return;
    if (!kHaveEmbree) refuse("--embree: this binary was built without Embree 3 (not found at configure time)");
    for (const std::string& text : texts) {
        if (text == "stream") {
            options.embree_stream = true;
            continue;
        }
        const auto width = parse_int(text);
        if (!width || std::find(std::begin(kEmbreePacketWidths), std::end(kEmbreePacketWidths), *width) ==
                          std::end(kEmbreePacketWidths))
            refuse(fmt::format(
                "--embree {}: expected 1, 4, 8, 16 (rtcIntersect1/4/8/16), stream (rtcIntersect1M) or none", text));
        push_unique(options.embree_packet_widths, *width);
    }
}

EmbreeQuality resolve_embree_quality(const std::optional<std::string>& text) {
    if (!text) return EmbreeQuality::high;
    if (!kHaveEmbree) refuse("--embree-quality: this binary was built without Embree 3 (not found at configure time)");
    if (*text == "low") return EmbreeQuality::low;
    if (*text == "medium") return EmbreeQuality::medium;
    if (*text == "high") return EmbreeQuality::high;
    refuse(fmt::format("--embree-quality {}: expected low, medium or high", *text));
}

/// Without --embree-isa, Embree's rows are capped as ours are: TRIDENT_ISA=avx2 gives both sides AVX2
/// kernels, so the pair compares like with like (a cap above what the CPU runs caps nothing).
EmbreeIsa embree_isa_of_cap() {
    const std::optional<IsaLevel> cap = isa_cap();
    if (!cap) return EmbreeIsa::native;
    const EmbreeIsa isa = *cap == IsaLevel::sse4 ? EmbreeIsa::sse42 : *cap == IsaLevel::avx2 ? EmbreeIsa::avx2 : EmbreeIsa::avx512;
    return cpu_runs(isa) ? isa : EmbreeIsa::native;
}

EmbreeIsa resolve_embree_isa(const std::optional<std::string>& text) {
    if (!text) return kHaveEmbree ? embree_isa_of_cap() : EmbreeIsa::native;
    if (!kHaveEmbree) refuse("--embree-isa: this binary was built without Embree 3 (not found at configure time)");
    for (EmbreeIsa isa : kAllEmbreeIsas)
        if (*text == to_string(isa)) {
            if (!cpu_runs(isa)) refuse(fmt::format("--embree-isa {}: this CPU does not run it", *text));
            return isa;
        }
    refuse(fmt::format("--embree-isa {}: expected native, sse4.2, avx2 or avx512", *text));
}

ReferenceChoice resolve_reference(const Arguments& args) {
    ReferenceChoice choice;
    if (args.reference_hits) {
        if (args.reference != "auto")
            refuse(fmt::format("--reference {} and --reference-hits: give one of them", args.reference));
        choice.source = ReferenceChoice::Source::file;
        choice.file = *args.reference_hits;
        if (!std::filesystem::exists(choice.file))
            refuse(fmt::format("--reference-hits {}: no such file or folder", choice.file.string()));
        return choice;
    }
    if (args.reference == "auto") return choice;
    if (args.reference == "self") {
        choice.source = ReferenceChoice::Source::self;
        return choice;
    }
    if (args.reference == "embree") {
        if (!kHaveEmbree) refuse("--reference embree: this binary was built without Embree 3");
        choice.source = ReferenceChoice::Source::embree;
        return choice;
    }
    const auto kind = parse_accel_kind(args.reference);
    if (!kind)
        refuse(
            fmt::format("--reference {}: expected auto, embree, self, brute, bvh, bvh2, kdtree or octree", args.reference));
    choice.source = ReferenceChoice::Source::structure;
    choice.structure = *kind;
    return choice;
}

std::vector<PairPartner> resolve_paired(const std::vector<std::string>& names, const std::vector<RayKind>& kinds) {
    std::vector<PairPartner> partners;
    for (const std::string& name : names) {
        if (name == "scalar")
            push_unique(partners, PairPartner::scalar);
        else if (name == "bvh")
            push_unique(partners, PairPartner::bvh);
        else if (name == "embree") {
            if (!kHaveEmbree) refuse("--paired embree: this binary was built without Embree 3");
            push_unique(partners, PairPartner::embree);
        } else if (name == "closest") {
            if (std::find(kinds.begin(), kinds.end(), RayKind::shadow) == kinds.end())
                refuse("--paired closest: pairs shadow rows only; add shadow to --rays");
            push_unique(partners, PairPartner::closest);
        } else
            refuse(fmt::format("--paired {}: expected scalar, bvh, embree or closest", name));
    }
    return partners;
}

std::vector<RayKind> resolve_ray_kinds(const std::vector<std::string>& names) {
    std::vector<RayKind> kinds;
    for (const std::string& name : names) {
        const auto kind = parse_ray_kind(name);
        if (!kind) refuse(fmt::format("--rays {}: expected primary, shadow or diffuse", name));
        push_unique(kinds, *kind);
    }
    if (kinds.empty()) kinds.push_back(RayKind::primary);
    return kinds;
}

BenchOptions resolve(const Arguments& args, const CLI::App& app) {
    BenchOptions options;
    if (args.width < 1 || args.height < 1 || args.width > kMaxImageSide || args.height > kMaxImageSide)
        refuse(fmt::format("--width/--height {}x{}: each must lie in 1..{}", args.width, args.height, kMaxImageSide));
    options.width = std::uint32_t(args.width);
    options.height = std::uint32_t(args.height);
    if (args.repeats < 1) refuse(fmt::format("--repeats {}: at least 1 (BENCHMARK.md asks for 5)", args.repeats));
    options.repeats = int(args.repeats);

    if (args.sweep) {
        if (!args.accel.empty()) refuse("--sweep measures only its own structure: leave out --accel");
        options.sweep = &sweep_or_throw(*args.sweep);
        options.structures = {options.sweep->structure};
    } else {
        options.structures = resolve_structures(args.accel);
    }
    options.traversals = resolve_traversals(args.simd);
    options.triangle_tests = resolve_triangle_tests(args.triangle_tests);
    options.slab_tests = resolve_slab_tests(args.slabs);
    options.ray_kinds = resolve_ray_kinds(args.rays);
    if (options.sweep && options.ray_kinds != std::vector<RayKind>{RayKind::primary})
        refuse("--sweep times primary rays only: leave out --rays");
    options.threads = resolve_threads(args.threads);
    resolve_embree(args.embree, app.count("--embree") > 0, options);
    options.embree_quality = resolve_embree_quality(args.embree_quality);
    options.embree_isa = resolve_embree_isa(args.embree_isa);
    options.reference = resolve_reference(args);

    options.scene_specs = args.scenes;
    options.manifest = args.manifest;
    options.only = args.only;
    options.dump_hits = args.dump_hits;
    options.csv = args.csv;
    options.json = args.json;
    options.markdown = args.markdown;
    options.quiet = args.quiet;
    options.scaling = args.scaling;
    options.vs_single = args.vs_single;
    options.last_occluder = args.last_occluder == "on";
    options.tile_culling = args.tile_culling == "frustum" ? TileCulling::frustum : TileCulling::off;
    options.paired = resolve_paired(args.paired, options.ray_kinds);
    options.bvh_width = args.bvh_width;
    options.bvh_builder = parse_bvh_builder(args.bvh_builder);
    return options;
}

void add_options(CLI::App& app, Arguments& args) {
    app.add_option("--scenes", args.manifest, "scene manifest (BENCHMARK.md's scenes.json): run its scenes");
    app.add_option("--only", args.only, "names of the scenes to run (built-in or manifest), comma separated")
        ->delimiter(',');
    app.add_option("--scene", args.scenes,
                   "a built-in scene name or an .obj file (camera framed automatically); repeatable");
    app.add_option("--accel", args.accel,
                   "structures, comma separated: bvh,bvh2,kdtree,octree,brute (default: all built but brute; bvh "
                   "is the wide BVH, bvh2 the binary one)")
        ->delimiter(',');
    app.add_option("--bvh-width", args.bvh_width,
                   "children per node of the bvh rows' tree: 4, 8 or 16 (default: 16 where AVX2 runs, else 8)")
        ->check(CLI::IsMember({4, 8, 16}));
    app.add_option("--bvh-builder", args.bvh_builder,
                   "builder of the bvh and bvh2 rows' trees: auto (default: spatial splits where the mesh has "
                   "large triangles and they lower the SAH, binned elsewhere; bvh2 always binned), binned, sweep, "
                   "or spatial (spatial splits, the higher-quality build)")
        ->check(CLI::IsMember(bvh_builder_names()));
    app.add_option("--simd", args.simd,
                   "traversals, comma separated: scalar,simd4,simd8,simd16 or auto (default scalar)")
        ->delimiter(',');
    app.add_option("--triangle-test", args.triangle_tests,
                   "triangle tests, comma separated: watertight,moller_trumbore (default watertight)")
        ->delimiter(',');
    app.add_option("--rays", args.rays, "ray kinds to time, comma separated: primary,shadow,diffuse (default primary)")
        ->delimiter(',');
    app.add_option("--slabs", args.slabs, "box tests of the traversals, comma separated: robust,fast (default robust)")
        ->delimiter(',');
    app.add_option("--threads", args.threads,
                   "thread counts, comma separated, or 'all' (default: all hardware threads)")
        ->delimiter(',');
    app.add_option("--width", args.width, "image width in pixels (default 1920)");
    app.add_option("--height", args.height, "image height in pixels (default 1080)");
    app.add_option("--repeats", args.repeats, "timed runs after one warm-up; the median is reported (default 5)");
    app.add_option("--reference", args.reference, "error reference: auto, embree, self, brute, bvh, bvh2, kdtree, octree");
    app.add_option("--reference-hits", args.reference_hits,
                   "another tracer's hit buffer, or a folder of SCENE.hits files");
    app.add_option("--dump-hits", args.dump_hits,
                   "folder to write our hit buffers to (SCENE.STRUCTURE.TRAVERSAL.hits)");
    app.add_option("--embree", args.embree,
                   "Embree rows, comma separated: 1,4,8,16 (rtcIntersect1/4/8/16), stream (rtcIntersect1M on 8x8 "
                   "pixel blocks, primary rays) or none (default: all)")
        ->delimiter(',');
    app.add_option("--embree-quality", args.embree_quality,
                   "how Embree's rows build their BVH: high (spatial splits, the default), medium (binned SAH) or "
                   "low (Morton codes); the Embree reference is always built with high");
    app.add_option("--embree-isa", args.embree_isa,
                   "the most advanced ISA Embree's rows may use: native, sse4.2, avx2 or avx512 (rtcNewDevice's "
                   "max_isa; default: TRIDENT_ISA's cap when it is set, else native); the Embree reference "
                   "always runs native");
    app.add_option("--sweep", args.sweep,
                   "sweep one build parameter: octree-depth, bvh-buckets, bvh-cost, kd-cost, kd-empty-bonus, "
                   "kd-perfect-splits, kd-depth");
    app.add_option("--csv", args.csv, "write every configuration as CSV");
    app.add_option("--json", args.json, "write machine info and every configuration as JSON (bench/plot.py reads it)");
    app.add_option("--markdown", args.markdown, "write the tables as Markdown (for bench/RESULTS.md)");
    app.add_flag("--quiet", args.quiet, "no progress on stderr");
    app.add_flag("--scaling", args.scaling,
                 "rows at more than one thread also time each render on one thread right after it; their "
                 "speed-up over one thread is the median of the pairs' ratios");
    app.add_flag("--vs-single", args.vs_single,
                 "packet rows of shadow and diffuse rays also time the same rays as single rays right after each "
                 "run; their speed-up over single rays is the median of the pairs' ratios");
    app.add_option("--last-occluder", args.last_occluder,
                   "shadow rows: each ray or packet first tests the triangles that stopped the one before it (on, "
                   "the default, where the structure can: the wide BVH), or only walks the tree (off: the structure "
                   "alone); the answers are the same")
        ->check(CLI::IsMember({"on", "off"}));
    app.add_option("--tile-culling", args.tile_culling,
                   "primary rows: a 16x16 image tile none of whose rays can reach the structure's top boxes (its "
                   "frustum tested against them) gets misses without its rays being made or traced (frustum, the "
                   "default, as the renderer does), or every ray is traced (off: the walks alone, as Embree's rows "
                   "trace every ray); the hits are the same")
        ->check(CLI::IsMember({"frustum", "off"}));
    app.add_option("--paired", args.paired,
                   "partners rows are timed against run by run, comma separated: scalar (primary rows: the same "
                   "structure's single rays), bvh (primary rows: the BVH at the same traversal), embree (Embree's "
                   "call of the same width on the same rays; primary rows also Embree's best, the faster of "
                   "rtcIntersect16 and its stream), closest (shadow rows: the same traversal's closest hit); each "
                   "ratio is the median of the pairs'")
        ->delimiter(',');
}

}  // namespace

std::optional<BenchOptions> parse_bench_options(int argc, char** argv) {
    CLI::App app{"trident-bench: build and trace BVH, KD-tree and Octree side by side (BENCHMARK.md)"};
    Arguments args;
    add_options(app, args);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        app.exit(e);
        return std::nullopt;
    } catch (const CLI::ParseError& e) {
        refuse(e.what());
    }
    BenchOptions options = resolve(args, app);
    options.command_line = quoted_command_line(argc, argv);
    return options;
}

}  // namespace trident::bench
