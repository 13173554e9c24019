// The slab test instantiated over xsimd batches gives, lane by lane, the scalar test's answer bit
// for bit: same hit or miss and the same entry distance.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "core/slab_test.h"
#include "each_arch.h"
#include "simd/packet.h"
#include "support/float_bits.h"
#include "support/random_scenes.h"

using namespace trident;
using trident::testing::bits_of;
using trident::testing::for_each_packet_arch;

namespace {

/// Random boxes (some flat on an axis), rays from random_rays (every fifth axis-parallel with +0
/// and -0) and rays whose origin lies exactly on a box face, parallel to it or not.
struct BoxCase {
    std::vector<Aabb> boxes;
    std::vector<Ray> rays;
};

BoxCase make_case(std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> centre(-1.0f, 1.0f), half(0.0f, 0.5f), unit(0.0f, 1.0f);
    BoxCase c;
    for (int i = 0; i < 64; ++i) {
        const Vec3f mid{centre(rng), centre(rng), centre(rng)};
        Vec3f extent{half(rng), half(rng), half(rng)};
        if (i % 8 == 0) extent[i / 8 % 3] = 0.0f;
        c.boxes.push_back({mid - extent, mid + extent});
    }
    c.rays = testing::random_rays(Aabb{{-1.5f, -1.5f, -1.5f}, {1.5f, 1.5f, 1.5f}}, 300, seed);
    for (std::size_t i = 0; i < c.boxes.size(); i += 4) {
        const Aabb& box = c.boxes[i];
        for (int axis = 0; axis < 3; ++axis)
            for (const float zero : {0.0f, -0.0f}) {
                Ray on_face{box.center(), Vec3f{1.0f, 0.5f, -0.25f}};
                on_face.origin[axis] = box.lo[axis];  // on the face; parallel to it, then crossing it
                on_face.dir[axis] = zero;
                c.rays.push_back(on_face);
                on_face.dir[axis] = std::signbit(zero) ? -1.0f : 1.0f;
                c.rays.push_back(on_face);
            }
    }
    for (Ray& ray : c.rays) {  // varied intervals, a few empty
        const float r = unit(rng);
        if (r < 0.05f)
            ray.tmin = 3.0f, ray.tmax = 2.0f;
        else if (r < 0.2f)
            ray.tmin = 1.0f;
        else if (r > 0.95f)
            ray.tmax = 0.5f;
        else if (r > 0.8f)
            ray.tmax = 2.0f;
    }
    return c;
}

struct EntryMismatches {
    std::size_t lanes = 0, hits = 0, wrong = 0;
    std::string first;
    void compare(bool scalar_hit, float scalar_entry, bool packet_hit, float packet_entry, const std::string& where) {
        ++lanes;
        hits += scalar_hit;
        if (scalar_hit == packet_hit && bits_of(scalar_entry) == bits_of(packet_entry)) return;
        ++wrong;
        if (first.empty()) first = where;
    }
};

/// Rays in packets (the last one partial), each box broadcast to all lanes.
template <class Arch>
void compare_ray_packets(const BoxCase& c, EntryMismatches& m) {
    using Float = xsimd::batch<float, Arch>;
    using L = Lanes<Float>;
    constexpr std::size_t width = Float::size;
    const std::span<const Ray> rays(c.rays);
    for (std::size_t first = 0; first < rays.size(); first += width) {
        const auto chunk = rays.subspan(first, std::min(width, rays.size() - first));
        const RayPacket<Arch> packet(chunk);
        for (std::size_t k = 0; k < c.boxes.size(); ++k) {
            Float entry;
            const std::uint32_t hit_bits =
                L::bits(intersect_slabs(packet.slab, Vec3T<Float>(c.boxes[k].lo), Vec3T<Float>(c.boxes[k].hi),
                                        packet.tmin, packet.tmax, entry));
            if ((hit_bits & ~L::bits(packet.active)) != 0) m.compare(false, 0, true, 0, "an inactive lane hit");
            const auto entries = L::to_array(entry);
            for (std::size_t i = 0; i < chunk.size(); ++i) {
                float scalar_entry;
                const bool scalar_hit = intersect_slabs(SlabRay(chunk[i].origin, chunk[i].dir), c.boxes[k].lo,
                                                        c.boxes[k].hi, chunk[i].tmin, chunk[i].tmax, scalar_entry);
                m.compare(scalar_hit, scalar_entry, (hit_bits >> i) & 1u, entries[i],
                          "ray " + std::to_string(first + i) + ", box " + std::to_string(k));
            }
        }
    }
}

/// One ray broadcast to all lanes against a different box per lane (the wide-node layout).
template <class Arch>
void compare_box_packets(const BoxCase& c, EntryMismatches& m) {
    using Float = xsimd::batch<float, Arch>;
    using L = Lanes<Float>;
    constexpr std::size_t width = Float::size;
    for (std::size_t r = 0; r < c.rays.size(); ++r) {
        const Ray& ray = c.rays[r];
        const SlabRayT<Float> slab(Vec3T<Float>(ray.origin), Vec3T<Float>(ray.dir));
        const SlabRay scalar_slab(ray.origin, ray.dir);
        for (std::size_t first = 0; first < c.boxes.size(); first += width) {
            const std::size_t count = std::min(width, c.boxes.size() - first);
            std::array<typename L::Array, 6> corners{};  // lo.x lo.y lo.z hi.x hi.y hi.z, lane by lane
            for (std::size_t i = 0; i < width; ++i) {
                const Aabb& box = c.boxes[first + std::min(i, count - 1)];
                for (int axis = 0; axis < 3; ++axis) {
                    corners[axis][i] = box.lo[axis];
                    corners[3 + axis][i] = box.hi[axis];
                }
            }
            const Vec3T<Float> lo(L::from_array(corners[0]), L::from_array(corners[1]), L::from_array(corners[2]));
            const Vec3T<Float> hi(L::from_array(corners[3]), L::from_array(corners[4]), L::from_array(corners[5]));
            Float entry;
            const std::uint32_t hit_bits =
                L::bits(intersect_slabs(slab, lo, hi, Float(ray.tmin), Float(ray.tmax), entry));
            const auto entries = L::to_array(entry);
            for (std::size_t i = 0; i < count; ++i) {
                const Aabb& box = c.boxes[first + i];
                float scalar_entry;
                const bool scalar_hit = intersect_slabs(scalar_slab, box.lo, box.hi, ray.tmin, ray.tmax, scalar_entry);
                m.compare(scalar_hit, scalar_entry, (hit_bits >> i) & 1u, entries[i],
                          "ray " + std::to_string(r) + ", box " + std::to_string(first + i));
            }
        }
    }
}

}  // namespace

TEST_CASE("packet slab test equals the scalar slab test bit for bit, rays or boxes in the lanes") {
    const BoxCase c = make_case(5);
    for_each_packet_arch([&]<class Arch>() {
        EntryMismatches rays, boxes;
        compare_ray_packets<Arch>(c, rays);
        compare_box_packets<Arch>(c, boxes);
        INFO("ray packets: ", rays.first, "; box packets: ", boxes.first);
        CHECK(rays.wrong == 0);
        CHECK(boxes.wrong == 0);
        CHECK(rays.lanes == c.rays.size() * c.boxes.size());
        CHECK(boxes.lanes == rays.lanes);
        CHECK(rays.hits > 0);
        CHECK(rays.hits < rays.lanes);
    });
}
