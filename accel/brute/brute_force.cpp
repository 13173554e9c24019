#include "accel/brute/brute_force.h"

#include <chrono>

namespace trident {

BruteForce BruteForce::build(const Mesh& mesh) {
    const auto start = std::chrono::steady_clock::now();
    BruteForce out;
    out.triangles_ = gather_triangles(mesh);
    out.stats_.structure = "brute";
    out.stats_.triangles = mesh.triangle_count();
    out.stats_.nodes = out.stats_.leaves = 1;
    out.stats_.references = out.stats_.max_leaf_size = mesh.triangle_count();
    out.stats_.mean_leaf_size = double(mesh.triangle_count());
    out.stats_.sah_cost = double(mesh.triangle_count());
    out.stats_.bytes = out.triangles_.size() * sizeof(Triangle);
    out.stats_.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return out;
}

}  // namespace trident
