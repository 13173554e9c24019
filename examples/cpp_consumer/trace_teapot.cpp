// Traces the built-in teapot (or an OBJ named on the command line, seen from its bounding box's
// front) through the interface trident's renderer uses: AnyAccel over each structure and
// trace_primary at the widest packets, checked against single rays.
#include <cstdio>
#include <exception>

#include "accel/any_accel.h"
#include "camera/camera.h"
#include "render/trace.h"
#include "scene/obj_loader.h"
#include "scenes/builtin.h"

int main(int argc, char** argv) try {
    using namespace trident;
    Scene scene = make_builtin_scene("teapot");
    if (argc > 1) {
        scene.mesh = load_obj(argv[1]);
        const Aabb box = scene.mesh.bounds();
        scene.camera.target = (box.lo + box.hi) * 0.5f;
        scene.camera.eye = scene.camera.target + Vec3f(0.0f, 0.0f, 2.0f * length(box.hi - box.lo));
    }
    const Camera camera(scene.camera, 160, 90);
    for (const AccelKind kind : {AccelKind::bvh, AccelKind::kdtree, AccelKind::octree}) {
        const AnyAccel accel = AnyAccel::build(kind, scene.mesh);
        const std::vector<Hit> single = trace_primary(accel, camera);
        const std::vector<Hit> packets = trace_primary(accel, camera, TriangleTest::watertight, widest_supported());
        std::size_t hits = 0, differing = 0;
        for (std::size_t i = 0; i < single.size(); ++i) {
            hits += single[i].is_hit();
            differing += single[i].triangle != packets[i].triangle || single[i].t != packets[i].t;
        }
        std::printf("%s: %zu of %zu rays hit, %zu differ between single rays and packets\n  %s\n", to_string(kind),
                    hits, single.size(), differing, accel.stats().to_line().c_str());
        if (hits == 0 || differing != 0) return 1;
    }
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "trace_teapot: %s\n", e.what());
    return 1;
}
