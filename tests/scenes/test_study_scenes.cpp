// Checks on the study's scenes in ../shared/scenes (BENCHMARK.md), each skipped with a message
// when that folder is absent: the repository never depends on it.
#include <doctest/doctest.h>

#include <filesystem>
#include <optional>

#include "accel/bvh/bvh.h"
#include "scene/obj_loader.h"

using namespace trident;

namespace {

/// The study scene's mesh, or nothing (with a message) when ../shared is not beside the repository.
std::optional<Mesh> study_mesh(const char* file) {
    const std::filesystem::path path = std::filesystem::path(TRIDENT_SHARED_DIR) / "scenes" / file;
    if (!std::filesystem::exists(path)) {
        MESSAGE("skipped: ", path.string(), " is absent");
        return std::nullopt;
    }
    return load_obj(path);
}

}  // namespace

TEST_CASE("Room: the binned SAH tree costs within 3% of the full-sweep tree") {
    // Room's clusters of small objects in a large space are what the refined split is for.
    const std::optional<Mesh> mesh = study_mesh("room.obj");
    if (!mesh) return;
    BvhOptions sweep;
    sweep.builder = BvhBuilder::sweep_sah;
    const double binned_cost = Bvh::build(*mesh).stats().sah_cost;
    const double sweep_cost = Bvh::build(*mesh, sweep).stats().sah_cost;
    MESSAGE("binned SAH ", binned_cost, " / sweep SAH ", sweep_cost, " = ", binned_cost / sweep_cost);
    CHECK(binned_cost <= 1.03 * sweep_cost);
}
