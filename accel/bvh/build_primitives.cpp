#include "accel/bvh/build_primitives.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace trident::bvh {

namespace {

constexpr std::size_t kGrain = 1 << 14;

Vec3f without_negative_zero(const Vec3f& v) { return v + Vec3f{0.0f}; }  // -0 + +0 = +0

struct RangeUnion {
    Aabb bounds, centroid_bounds;

    void join(const RangeUnion& other) {
        bounds.extend(other.bounds);
        centroid_bounds.extend(other.centroid_bounds);
    }
};

}  // namespace

HugePageArray<PrimitiveRef> make_primitive_refs(const Mesh& mesh) {
    HugePageArray<PrimitiveRef> refs(mesh.triangle_count());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, refs.size(), kGrain), [&](const auto& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            const Aabb box = triangle_of(mesh, i).bounds();
            refs[i] = PrimitiveRef({without_negative_zero(box.lo), without_negative_zero(box.hi)}, TriangleId(i));
        }
    });
    return refs;
}

BuildRange whole_range(std::span<const PrimitiveRef> refs) {
    const RangeUnion all = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, refs.size(), kGrain), RangeUnion{},
        [&](const auto& r, RangeUnion acc) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                acc.bounds.extend(refs[i].bounds());
                acc.centroid_bounds.extend(refs[i].centroid());
            }
            return acc;
        },
        [](RangeUnion a, const RangeUnion& b) {
            a.join(b);
            return a;
        });
    return {0, std::uint32_t(refs.size()), all.bounds, all.centroid_bounds};
}

}  // namespace trident::bvh
