#pragma once
// trident-bench's command line, parsed and checked: every bad value is refused here with one line
// naming the option, before anything is loaded or built.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "accel/any_accel.h"
#include "bench/embree_baseline.h"
#include "bench/ray_sets.h"
#include "bench/sweep.h"
#include "bench/traversal.h"
#include "core/intersect_triangle.h"
#include "core/slab_test.h"
#include "render/trace.h"

namespace trident::bench {

inline constexpr std::uint32_t kMaxImageSide = 16384;
/// The brute force is refused above this many triangles: W x H x N triangle tests would take hours.
inline constexpr std::size_t kBruteMaxTriangles = 100000;
/// Embree's ray-packet calls: rtcIntersect1 (one ray), rtcIntersect4 / 8 / 16.
inline constexpr int kEmbreePacketWidths[] = {1, 4, 8, 16};

/// What the error columns compare each configuration with.
struct ReferenceChoice {
    enum class Source {
        automatic,  // Embree when built, else the BVH when built, else the brute force
        embree,
        structure,  // one of ours, traced once per scene
        self,       // each configuration with its own trace: the error must be exactly zero
        file,       // a hit buffer from another tracer, or a folder of SCENE.hits files
    };
    Source source = Source::automatic;
    AccelKind structure = AccelKind::bvh;
    std::filesystem::path file;
};

/// What a row can be timed against in pairs (--paired): the partner's render runs right after
/// each of the row's, on the same rays, so the two drift together on a shared machine.
enum class PairPartner {
    scalar,   // the same structure's single-ray traversal (packet rows)
    bvh,      // the BVH at the same traversal (KD-tree and octree rows)
    embree,   // Embree's call of the same width on the same rays: rtcIntersect1/N, or rtcOccluded1/N
    closest,  // shadow rows: the same traversal's closest hit on the same shadow rays
};

struct BenchOptions {
    std::vector<std::string> scene_specs;           // --scene: built-in names or .obj paths
    std::optional<std::filesystem::path> manifest;  // --scenes
    std::vector<std::string> only;                  // --only: names to keep
    std::vector<AccelKind> structures;
    int bvh_width = BvhOptions{}.width;  // --bvh-width: the wide BVH's children per node (bvh rows)
    BvhBuilder bvh_builder = BvhOptions{}.builder;  // --bvh-builder: bvh and bvh2 rows
    std::vector<Traversal> traversals;
    std::vector<TriangleTest> triangle_tests;  // --triangle-test (default watertight)
    std::vector<SlabTest> slab_tests;          // --slabs (default robust)
    std::vector<RayKind> ray_kinds;            // --rays (default primary only)
    std::vector<int> threads;
    std::vector<int> embree_packet_widths;               // --embree 1,4,8,16: Embree's packet rows
    bool embree_stream = false;                          // --embree stream: rtcIntersect1M on 8x8 blocks
    EmbreeQuality embree_quality = EmbreeQuality::high;  // --embree-quality, for Embree's rows (not its reference)
    EmbreeIsa embree_isa = EmbreeIsa::native;            // --embree-isa, for Embree's rows (not its reference)
    std::uint32_t width = 1920, height = 1080;
    int repeats = 5;
    ReferenceChoice reference;
    std::optional<std::filesystem::path> dump_hits, csv, json, markdown;
    const SweepSpec* sweep = nullptr;
    bool quiet = false;
    /// --scaling: rows at more than one thread also time each render on one thread right after it.
    bool scaling = false;
    /// --vs-single: packet rows of shadow and diffuse rays also time the same rays as single rays
    /// right after each run.
    bool vs_single = false;
    /// --last-occluder: shadow rows test the occluder of the ray or packet before first
    /// (StreamTraversal::last_occluder).
    bool last_occluder = true;
    /// --tile-culling: primary rows skip the image tiles whose frustum misses the structure's top
    /// boxes (TileCulling::frustum), or trace every ray (off).
    TileCulling tile_culling = TileCulling::frustum;
    /// --paired: the partners rows of ours are timed against, each run by run.
    std::vector<PairPartner> paired;
    bool pairs_with(PairPartner partner) const {
        return std::find(paired.begin(), paired.end(), partner) != paired.end();
    }
    std::string command_line;

    /// Whether Embree has rows of its own in this run (never in a sweep).
    bool runs_embree() const { return !sweep && (!embree_packet_widths.empty() || embree_stream); }
};

/// Empty when --help was asked for (and printed). Throws std::invalid_argument with one line
/// naming the option on any bad value.
std::optional<BenchOptions> parse_bench_options(int argc, char** argv);

}  // namespace trident::bench
