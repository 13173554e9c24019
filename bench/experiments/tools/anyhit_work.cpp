// The wide BVH's work per shadow ray, closest hit against any hit, split by whether the ray is
// occluded (issue 31's "any hit at least 1.3x closest hit"): what the any-hit query can save, in
// node visits and triangle tests, on the rays trident-bench traces. Not part of the build: a trial
// tool, its figures in ../bvh-traversal.md. Built against a native build's libraries, from build-native/
// (one command):
//   g++ -std=c++20 -O3 -DNDEBUG -march=native -ffp-contract=off -DFMT_SHARED -DTRIDENT_KERNELS_W4=1
//     -DTRIDENT_KERNELS_W8=1 -DTRIDENT_KERNELS_W16=1 -DTRIDENT_PORTABLE_BUILD=0 -I../src -I..
//     -isystem /usr/include/stb ../bench/experiments/tools/anyhit_work.cpp ../bench/ray_sets.cpp
//     -o anyhit_work libtrident_app.a libtrident_bvh.a libtrident_kdtree.a libtrident_octree.a
//     libtrident_scenes.a libtrident_accel.a libtrident_simd.a libtrident_core.a -ltbb -ltinyobjloader
//     -lfmt -lstb
// then, from the repository: build-native/anyhit_work ../shared/scenes/scenes.json teapot bunny ...
//
// Rays: trident-bench's shadow rays (bench/ray_sets.h) of the BENCHMARK.md camera at 1920x1080, the
// ones it traces (tmax > tmin), in its order; the wide BVH as `--accel bvh` builds it by default.
#include <cstdio>
#include <cstdlib>

#include "accel/any_accel.h"
#include "bench/ray_sets.h"
#include "camera/camera.h"
#include "scene/scene_source.h"

using namespace trident;

namespace {

struct PerRay {
    double nodes, triangles;
};
PerRay per_ray(const TraversalCounters& c, std::size_t rays) {
    return {double(c.nodes_visited) / double(rays), double(c.triangles_tested) / double(rays)};
}

template <class Wide>
void measure(const char* name, const Wide& bvh, const std::vector<Ray>& rays) {
    TraversalCounters closest, closest_unoccluded, any, any_last;
    std::size_t traced = 0, occluded = 0;
    LastOccluder last;  // one list, as a thread's share of single rays is traced
    for (const Ray& ray : rays) {
        if (!(ray.tmax > ray.tmin)) continue;
        ++traced;
        TraversalCounters c, a, l;
        const bool blocked = bvh.template intersect<TriangleTest::watertight>(ray, c).is_hit();
        const bool blocked_any = bvh.template occluded<TriangleTest::watertight>(ray, a);
        const bool blocked_last = bvh.template occluded<TriangleTest::watertight>(ray, l, last);
        if (blocked != blocked_any || blocked != blocked_last) {
            std::fprintf(stderr, "%s: the three queries disagree on a ray\n", name);
            std::exit(1);
        }
        closest += c;
        any += a;
        any_last += l;
        if (blocked)
            ++occluded;
        else
            closest_unoccluded += c;
    }
    const PerRay c = per_ray(closest, traced), u = per_ray(closest_unoccluded, traced), a = per_ray(any, traced),
                 l = per_ray(any_last, traced);
    // Work ratios, closest hit over the other: above 1 the other does less.
    std::printf(
        "| %s | %zu | %.1f%% | %.2f / %.2f | %.2f / %.2f | %.2f / %.2f | %.3f / %.3f | %.3f / %.3f | "
        "%.3f / %.3f |\n",
        name, traced, 100.0 * double(occluded) / double(traced), c.nodes, c.triangles, a.nodes, a.triangles, l.nodes,
        l.triangles, c.nodes / a.nodes, c.triangles / a.triangles, c.nodes / l.nodes, c.triangles / l.triangles,
        c.nodes / u.nodes, c.triangles / u.triangles);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: anyhit_work SCENES_JSON SCENE...\n");
        return 2;
    }
    std::printf(
        "| scene | shadow rays | occluded | closest hit: nodes / triangles per ray | any hit | any hit, "
        "last occluder first | closest over any | closest over any, last occluder | ceiling: closest "
        "over its unoccluded rays' share |\n|---|---|---|---|---|---|---|---|---|\n");
    for (int a = 2; a < argc; ++a) {
        const LoadedScene loaded = load_scene(argv[a], std::filesystem::path(argv[1]));
        const Camera camera(loaded.scene.camera, 1920, 1080);
        const bench::SceneRaySets sets = bench::make_scene_ray_sets(loaded.scene, camera, {bench::RayKind::shadow});
        const AnyAccel accel = AnyAccel::build(AccelKind::bvh, loaded.scene.mesh);
        accel.visit([&](const auto& structure) {
            if constexpr (requires { std::decay_t<decltype(structure)>::block_size; })
                measure(argv[a], structure, sets.shadow.rays);
        });
    }
}
