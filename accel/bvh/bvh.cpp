#include "accel/bvh/bvh.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <stdexcept>
#include <string>

#include "accel/bvh/binned_sah_splitter.h"
#include "accel/bvh/build_primitives.h"
#include "accel/bvh/bvh_stats.h"
#include "accel/bvh/spatial_split_builder.h"
#include "accel/bvh/sweep_sah_splitter.h"
#include "accel/bvh/tree_builder.h"

namespace trident {

namespace {

constexpr std::size_t kGatherGrain = 1 << 14;

template <class IdOf>
HugePageArray<TriangleId> gather_ids(std::size_t count, IdOf id_of) {
    HugePageArray<TriangleId> ids(count);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kGatherGrain), [&](const auto& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) ids[i] = id_of(i);
    });
    return ids;
}

}  // namespace

namespace bvh {

BinaryTree build_binary_tree(const Mesh& mesh, const BvhOptions& options) {
    options.validate();
    if (mesh.triangle_count() >= std::size_t(kNoTriangle))
        throw std::length_error("Bvh: " + std::to_string(mesh.triangle_count()) + " triangles exceed 32-bit ids");
    if (options.builder == BvhBuilder::spatial_sah) {
        SpatialSplitTree tree = build_with_spatial_splits(mesh, options);
        return {std::move(tree.nodes), std::move(tree.leaf_ids)};
    }
    HugePageArray<PrimitiveRef> refs = make_primitive_refs(mesh);
    const BuildRange root = whole_range(refs);
    if (options.builder == BvhBuilder::binned_sah || options.builder == BvhBuilder::automatic) {
        BinnedSahSplitter splitter(refs, options);
        HugePageArray<BvhNode> nodes = TreeBuilder(splitter, options).build(root);
        return {std::move(nodes), gather_ids(refs.size(), [&](std::size_t i) { return refs[i].id; })};
    }
    SweepSahSplitter splitter(refs, options);
    HugePageArray<BvhNode> nodes = TreeBuilder(splitter, options).build(root);
    return {std::move(nodes), gather_ids(refs.size(), [&](std::size_t i) { return splitter.leaf_order()[i]; })};
}

}  // namespace bvh

Bvh Bvh::build(const Mesh& mesh, const BvhOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    bvh::BinaryTree tree = bvh::build_binary_tree(mesh, options);
    Bvh result;
    result.options_ = options;
    if (options.builder == BvhBuilder::automatic) result.options_.builder = BvhBuilder::binned_sah;  // what was built
    result.nodes_ = std::move(tree.nodes);
    result.triangle_ids_ = std::move(tree.leaf_ids);
    result.triangles_.resize(result.triangle_ids_.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, result.triangles_.size(), kGatherGrain), [&](const auto& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i)
            result.triangles_[i] = triangle_of(mesh, result.triangle_ids_[i]);
    });

    const double build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    result.stats_ = bvh_stats(result.nodes_, mesh.triangle_count(), result.options_);
    result.stats_.build_ms = build_ms;
    return result;
}

}  // namespace trident
