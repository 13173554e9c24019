// RayPacket and HitPacket: loading full and partial packets, the per-packet precomputed data,
// and a closest-hit loop over packets that reproduces the scalar loop bit for bit.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/intersect_triangle.h"
#include "each_arch.h"
#include "simd/hit_lanes.h"
#include "simd/packet.h"
#include "support/float_bits.h"
#include "support/random_scenes.h"

using namespace trident;
using trident::testing::bits_of;
using trident::testing::for_each_packet_arch;

namespace {

/// Rays with distinct values in every field; directions in the octant given by `negative`
/// (bit a: component a negative; a zero component is -0 when negative).
std::vector<Ray> distinct_rays(std::size_t count, int negative) {
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < count; ++i) {
        const float f = float(i);
        Vec3f dir{1.0f + f, 0.5f * f, 2.0f};
        for (int axis = 0; axis < 3; ++axis)
            if ((negative >> axis) & 1) dir[axis] = -dir[axis];  // 0.5 * 0 becomes -0
        rays.push_back({{f, 10.0f + f, -f}, dir, 0.25f * f, 100.0f + f});
    }
    return rays;
}

template <class Arch>
void check_lanes(const RayPacket<Arch>& packet, std::span<const Ray> rays) {
    using L = Lanes<xsimd::batch<float, Arch>>;
    constexpr std::size_t width = RayPacket<Arch>::width;
    const auto ox = L::to_array(packet.origin.x), oy = L::to_array(packet.origin.y), oz = L::to_array(packet.origin.z);
    const auto dx = L::to_array(packet.dir.x), dy = L::to_array(packet.dir.y), dz = L::to_array(packet.dir.z);
    const auto ix = L::to_array(packet.slab.inv_dir.x), iy = L::to_array(packet.slab.inv_dir.y);
    const auto iz = L::to_array(packet.slab.inv_dir.z);
    const auto t0 = L::to_array(packet.tmin), t1 = L::to_array(packet.tmax);
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < width; ++i) {
        const bool live = i < rays.size();
        const Ray& ray = rays[live ? i : 0];  // inactive lanes copy the first ray
        wrong += bits_of(ox[i]) != bits_of(ray.origin.x) || bits_of(oy[i]) != bits_of(ray.origin.y) ||
                 bits_of(oz[i]) != bits_of(ray.origin.z);
        wrong += bits_of(dx[i]) != bits_of(ray.dir.x) || bits_of(dy[i]) != bits_of(ray.dir.y) ||
                 bits_of(dz[i]) != bits_of(ray.dir.z);
        const SlabRay scalar_slab(ray.origin, ray.dir);
        wrong += bits_of(ix[i]) != bits_of(scalar_slab.inv_dir.x) || bits_of(iy[i]) != bits_of(scalar_slab.inv_dir.y) ||
                 bits_of(iz[i]) != bits_of(scalar_slab.inv_dir.z);
        wrong += live ? (t0[i] != ray.tmin || t1[i] != ray.tmax) : (t0[i] != kInfinity || t1[i] != -kInfinity);
        for (int axis = 0; axis < 3; ++axis)
            wrong += bool((simd::mask_bits(packet.dir_negative[axis]) >> i) & 1u) != std::signbit(ray.dir[axis]);
    }
    CHECK(wrong == 0);
    CHECK(simd::mask_bits(packet.active) == (1u << rays.size()) - 1u);
}

}  // namespace

TEST_CASE("a ray packet loads every count of rays, leaves the rest inactive and finds the shared octant") {
    for_each_packet_arch([]<class Arch>() {
        constexpr std::size_t width = RayPacket<Arch>::width;
        for (int octant = 0; octant < 8; ++octant) {
            CAPTURE(octant);
            for (std::size_t count = 1; count <= width; ++count) {
                CAPTURE(count);
                const std::vector<Ray> rays = distinct_rays(count, octant);
                const RayPacket<Arch> packet(rays);
                check_lanes(packet, rays);
                CHECK(packet.shares_octant());
                CHECK(packet.octant == octant);
            }
        }
    });
}

TEST_CASE("a ray packet read through an index holds the indexed rays, as one built from their copies") {
    for_each_packet_arch([]<class Arch>() {
        constexpr std::size_t width = RayPacket<Arch>::width;
        const std::vector<Ray> stream = distinct_rays(3 * width, 0);
        for (std::size_t count = 1; count <= width; ++count) {
            CAPTURE(count);
            // Every third ray backwards from the end: an order unlike the stream's.
            std::vector<std::size_t> index;
            std::vector<Ray> copies;
            for (std::size_t k = 0; k < count; ++k) {
                index.push_back(stream.size() - 1 - 3 * k);
                copies.push_back(stream[index.back()]);
            }
            const RayPacket<Arch> packet(stream, index);
            check_lanes(packet, copies);
            CHECK(packet.octant == RayPacket<Arch>(copies).octant);
        }
    });
}

TEST_CASE("a ray packet whose active lanes point into different octants has no shared octant") {
    for_each_packet_arch([]<class Arch>() {
        constexpr std::size_t width = RayPacket<Arch>::width;
        for (int axis = 0; axis < 3; ++axis) {
            std::vector<Ray> rays = distinct_rays(width, 0);
            rays.back().dir[axis] = -rays.back().dir[axis];
            CHECK(RayPacket<Arch>(rays).octant == RayPacket<Arch>::kMixedOctant);
            // The differing ray left out: the inactive lane copies ray 0, so the octant is shared.
            CHECK(RayPacket<Arch>(std::span<const Ray>(rays).first(width - 1)).octant == 0);
        }
        std::vector<Ray> zeros = distinct_rays(2, 0);
        zeros[0].dir = {1.0f, 0.0f, 1.0f};
        zeros[1].dir = {1.0f, -0.0f, 1.0f};  // -0 counts as negative, as 1 / -0 = -inf does
        CHECK(RayPacket<Arch>(zeros).octant == RayPacket<Arch>::kMixedOctant);
    });
}

TEST_CASE("a hit packet records hits per lane and stores misses as Hit{}") {
    for_each_packet_arch([]<class Arch>() {
        using Float = xsimd::batch<float, Arch>;
        constexpr std::size_t width = RayPacket<Arch>::width;
        const std::vector<Ray> rays = distinct_rays(width, 0);
        const RayPacket<Arch> packet(std::span<const Ray>(rays).first(width - 1));
        HitPacket<Arch> hits(packet);
        CHECK(xsimd::all(hits.t == packet.tmax));
        std::array<bool, width> even{};
        for (std::size_t i = 0; i < width; i += 2) even[i] = true;
        hits.record(xsimd::batch_bool<float, Arch>::load_unaligned(even.data()), 42,
                    {Float(3.0f), Float(0.25f), Float(0.5f)});
        std::vector<Hit> stored(width - 1, Hit{7, 1.0f, 1.0f, 1.0f});
        const simd::HitLanes<Arch> lanes(hits);
        for (std::size_t i = 0; i < stored.size(); ++i) lanes.store_lane(i, &stored[i]);
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < stored.size(); ++i) {
            const Hit expected = even[i] ? Hit{42, 3.0f, 0.25f, 0.5f} : Hit{};
            wrong += stored[i].triangle != expected.triangle || stored[i].t != expected.t ||
                     stored[i].u != expected.u || stored[i].v != expected.v;
        }
        CHECK(wrong == 0);
    });
}

TEST_CASE("hit lanes write each lane's hit, a miss as Hit{}, by block rows and one by one") {
    for_each_packet_arch([]<class Arch>() {
        using Float = xsimd::batch<float, Arch>;
        constexpr std::size_t width = RayPacket<Arch>::width;
        constexpr std::size_t row_lanes = width == 4 ? 2 : 4;   // the pixel blocks' (image_tiles.h)
        const std::vector<Ray> rays = distinct_rays(width, 0);  // tmax 100 + i: a miss keeps it
        const RayPacket<Arch> packet(rays);
        HitPacket<Arch> hits(packet);
        // Lane i hits triangle 10 + i at t = i + 1 when i is not a multiple of 3, every field
        // distinct; the misses' u and v are set too, which the stores must not pass on.
        std::array<float, width> t{}, u{}, v{};
        std::array<std::uint32_t, width> ids{};
        for (std::size_t i = 0; i < width; ++i) {
            const bool hit = i % 3 != 0;
            ids[i] = hit ? std::uint32_t(10 + i) : kNoTriangle;
            t[i] = hit ? float(i) + 1.0f : rays[i].tmax;
            u[i] = 0.125f * float(i + 1), v[i] = 0.0625f * float(i + 1);
        }
        hits.triangle = xsimd::batch<std::uint32_t, Arch>::load_unaligned(ids.data());
        hits.t = Float::load_unaligned(t.data());
        hits.u = Float::load_unaligned(u.data());
        hits.v = Float::load_unaligned(v.data());
        const auto expected = [&](std::size_t i) {
            return ids[i] == kNoTriangle ? Hit{} : Hit{ids[i], t[i], u[i], v[i]};
        };
        const auto same = [](const Hit& a, const Hit& b) {
            return a.triangle == b.triangle && bits_of(a.t) == bits_of(b.t) && bits_of(a.u) == bits_of(b.u) &&
                   bits_of(a.v) == bits_of(b.v);
        };
        const simd::HitLanes<Arch> lanes(hits);
        // Rows into a wider image, so that a store past its row would show in the gaps.
        constexpr std::size_t stride = row_lanes + 3;
        std::vector<Hit> image(width / row_lanes * stride, Hit{7, 1.0f, 1.0f, 1.0f});
        lanes.template store_rows<row_lanes>([&](std::size_t row) { return image.data() + row * stride; });
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < width; ++i)
            wrong += !same(image[i / row_lanes * stride + i % row_lanes], expected(i));
        for (std::size_t row = 0; row < width / row_lanes; ++row)
            for (std::size_t k = row_lanes; k < stride; ++k)
                wrong += !same(image[row * stride + k], Hit{7, 1.0f, 1.0f, 1.0f});
        CHECK(wrong == 0);
        std::vector<Hit> one_by_one(width, Hit{7, 1.0f, 1.0f, 1.0f});
        for (std::size_t i = 0; i < width; ++i) lanes.store_lane(width - 1 - i, &one_by_one[i]);
        wrong = 0;
        for (std::size_t i = 0; i < width; ++i) wrong += !same(one_by_one[i], expected(width - 1 - i));
        CHECK(wrong == 0);
    });
}

TEST_CASE("closest hits over packets equal the scalar closest hits bit for bit") {
    const Mesh soup = testing::random_soup(150, 21, 0.3f);
    const std::vector<Triangle> triangles = gather_triangles(soup);
    std::vector<Ray> rays = testing::random_rays(soup.bounds(), 203, 22);  // a partial last packet
    for (std::size_t i = 0; i < rays.size(); i += 7) rays[i].tmax = 1.0f;
    for (const TriangleTest test : {TriangleTest::watertight, TriangleTest::moller_trumbore}) {
        const std::string test_name = to_string(test);
        CAPTURE(test_name);
        auto closest_scalar = [&]<TriangleTest Test>(const Ray& ray) {
            const TriangleIntersector<Test> isect(ray);
            Hit best;
            best.t = ray.tmax;
            TriangleHit h;
            for (std::size_t k = 0; k < triangles.size(); ++k)
                if (isect.intersect(triangles[k], best.t, h)) best = {TriangleId(k), h.t, h.u, h.v};
            return best.is_hit() ? best : Hit{};
        };
        auto closest_packets = [&]<TriangleTest Test, class Arch>() {
            using Float = xsimd::batch<float, Arch>;
            constexpr std::size_t width = Float::size;
            std::vector<Hit> out(rays.size());
            for (std::size_t first = 0; first < rays.size(); first += width) {
                const std::size_t count = std::min(width, rays.size() - first);
                const RayPacket<Arch> packet(std::span<const Ray>(rays).subspan(first, count));
                const auto isect = packet_intersector<Test>(packet);
                HitPacket<Arch> hits(packet);
                TriangleHitT<Float> h{};
                for (std::size_t k = 0; k < triangles.size(); ++k)
                    hits.record(isect.intersect(triangles[k], hits.t, h) & packet.active, TriangleId(k), h);
                const simd::HitLanes<Arch> lanes(hits);
                for (std::size_t i = 0; i < count; ++i) lanes.store_lane(i, &out[first + i]);
            }
            return out;
        };
        for_each_packet_arch([&]<class Arch>() {
            const std::vector<Hit> packet_hits =
                test == TriangleTest::watertight
                    ? closest_packets.template operator()<TriangleTest::watertight, Arch>()
                    : closest_packets.template operator()<TriangleTest::moller_trumbore, Arch>();
            std::size_t wrong = 0, hit_count = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) {
                const Hit s = test == TriangleTest::watertight
                                  ? closest_scalar.template operator()<TriangleTest::watertight>(rays[i])
                                  : closest_scalar.template operator()<TriangleTest::moller_trumbore>(rays[i]);
                const Hit& p = packet_hits[i];
                hit_count += s.is_hit();
                wrong += s.triangle != p.triangle || bits_of(s.t) != bits_of(p.t) || bits_of(s.u) != bits_of(p.u) ||
                         bits_of(s.v) != bits_of(p.v);
            }
            CHECK(wrong == 0);
            CHECK(hit_count > rays.size() / 4);
        });
    }
}
