// Ray packets through the BVH against the single-ray traversal, at every width this machine runs
// and with the single-ray switch off, at its default and taking every subtree: closest hits with
// the same t bits (and the same triangle, u and v unless two triangles tie at that t), the same
// any-hit answers, on camera pixel blocks of the built-in scenes, incoherent and mixed-sign
// packets, rays starting on box planes, windowed rays, partial packets and lanes switched off.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "bvh_test_helpers.h"
#include "simd/each_arch.h"
#include "support/random_scenes.h"

using namespace trident;
using namespace trident::testing;

namespace {

/// Which lanes of each packet to switch off, by lane index.
using LaneFilter = std::function<bool(std::size_t)>;

struct PacketComparison {
    std::size_t lanes = 0;        // lanes compared
    std::size_t hits = 0;         // of them, single-ray hits (to see the test is not vacuous)
    std::size_t ties = 0;         // lanes that kept another triangle hit at the same t
    std::size_t closest = 0;      // lanes whose closest hit differs otherwise
    std::size_t shared_ties = 0;  // ties in packets whose lanes share an octant, where none may occur
    std::size_t occluded = 0;     // lanes whose any-hit answer differs
    std::size_t untouched = 0;    // lanes not traced whose hit record changed anyway
    std::size_t padding = 0;      // lanes not traced reported occluded

    void require_agreement() const {
        CHECK(lanes > 0);
        CHECK(closest == 0);
        CHECK(shared_ties == 0);
        CHECK(occluded == 0);
        CHECK(untouched == 0);
        CHECK(padding == 0);
    }
};

bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }
bool same_bits(const Hit& a, const Hit& b) {
    return a.triangle == b.triangle && same_bits(a.t, b.t) && same_bits(a.u, b.u) && same_bits(a.v, b.v);
}

/// The raw lanes of a hit packet (misses as they are, not as Hit{}).
template <class Arch>
struct HitLanes {
    static constexpr std::size_t width = HitPacket<Arch>::width;
    std::array<std::uint32_t, width> triangle;
    std::array<float, width> t, u, v;

    explicit HitLanes(const HitPacket<Arch>& hits) {
        hits.triangle.store_unaligned(triangle.data());
        hits.t.store_unaligned(t.data());
        hits.u.store_unaligned(u.data());
        hits.v.store_unaligned(v.data());
    }
    Hit lane(std::size_t i) const { return {triangle[i], t[i], u[i], v[i]}; }
};

/// Whether the traced lanes agree on the sign of every direction component (dir < 0, the
/// single-ray traversal's rule for the near child): then every lane meets its nodes in the
/// single-ray order and ties resolve alike.
bool lanes_share_octant(std::span<const Ray> rays, const std::vector<bool>& traced) {
    int octant = -1;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!traced[i]) continue;
        const int lane = int(rays[i].dir.x < 0.0f) | int(rays[i].dir.y < 0.0f) << 1 | int(rays[i].dir.z < 0.0f) << 2;
        if (octant >= 0 && lane != octant) return false;
        octant = lane;
    }
    return true;
}

/// The pixel block of a packet: 2x2, 4x2 or 4x4.
constexpr std::pair<int, int> packet_block(std::size_t width) {
    return {width == 4 ? 2 : 4, int(width) / (width == 4 ? 2 : 4)};
}

/// Whether `got` is the single-ray triangle test's hit of `ray` on its triangle at exactly the t
/// of `expected`: another triangle of a tie.
template <TriangleTest Test>
bool is_tie(const Mesh& mesh, const Ray& ray, const Hit& got, const Hit& expected) {
    if (!got.is_hit() || !expected.is_hit() || !same_bits(got.t, expected.t)) return false;
    TriangleHit h;
    const bool hit = TriangleIntersector<Test>(ray).intersect(triangle_of(mesh, got.triangle), kInfinity, h);
    return hit && same_bits(h.t, got.t) && same_bits(h.u, got.u) && same_bits(h.v, got.v);
}

/// Traces `rays` in packets of `rays_per_packet` consecutive rays (the width when 0; the last
/// packet may be partial) with the lanes `off` names switched off, closest hit and any hit, and
/// compares every lane with the single-ray traversal. A lane switched off, or with tmin > tmax,
/// must keep the record it arrived with and never be occluded.
template <class Arch, int SingleRayLanes, TriangleTest Test = TriangleTest::watertight,
          SlabTest Slabs = SlabTest::robust>
PacketComparison compare_packets(const Bvh& bvh, const Mesh& mesh, std::span<const Ray> rays,
                                 std::size_t rays_per_packet = 0, const LaneFilter& off = {}) {
    constexpr std::size_t width = RayPacket<Arch>::width;
    using Mask = typename RayPacket<Arch>::Mask;
    const std::size_t step = rays_per_packet == 0 ? width : std::min(rays_per_packet, width);
    PacketComparison out;
    NoCounters none;
    for (std::size_t first = 0; first < rays.size(); first += step) {
        const std::span<const Ray> chunk = rays.subspan(first, std::min(step, rays.size() - first));
        RayPacket<Arch> packet(chunk);
        std::array<bool, width> live{};
        for (std::size_t i = 0; i < chunk.size(); ++i) live[i] = !(off && off(i));
        packet.active = packet.active & Mask::load_unaligned(live.data());

        const HitPacket<Arch> arrived(packet);
        HitPacket<Arch> hits(packet);
        bvh.intersect<Test, Slabs, Arch, NoCounters, SingleRayLanes>(packet, hits, none);
        const std::uint32_t occluded =
            simd::mask_bits(bvh.occluded<Test, Slabs, Arch, NoCounters, SingleRayLanes>(packet, none));
        const HitLanes<Arch> before(arrived), after(hits);
        std::vector<bool> traced(width);
        for (std::size_t i = 0; i < chunk.size(); ++i) traced[i] = live[i] && chunk[i].tmin <= chunk[i].tmax;
        const bool shared_octant = lanes_share_octant(chunk, traced);

        for (std::size_t i = 0; i < width; ++i) {
            if (!traced[i]) {
                out.untouched += !same_bits(before.lane(i), after.lane(i));
                out.padding += (occluded >> i) & 1u;
                continue;
            }
            ++out.lanes;
            const Hit expected = bvh.intersect<Test, Slabs>(chunk[i], none);
            out.hits += expected.is_hit();
            const Hit got = after.lane(i).is_hit() ? after.lane(i) : Hit{};
            if (!same_bits(got, expected)) {
                if (is_tie<Test>(mesh, chunk[i], got, expected)) {
                    ++out.ties;
                    out.shared_ties += shared_octant;
                } else {
                    ++out.closest;
                }
            }
            out.occluded += bool((occluded >> i) & 1u) != bvh.occluded<Test, Slabs>(chunk[i], none);
        }
    }
    return out;
}

/// Every packet width this machine runs, each with the single-ray switch off, at its default and
/// taking every subtree, on the same rays. Returns the ties met (lanes that kept another triangle).
template <TriangleTest Test = TriangleTest::watertight, SlabTest Slabs = SlabTest::robust>
std::size_t check_packets(const Bvh& bvh, const Mesh& mesh, std::span<const Ray> rays, const LaneFilter& off = {},
                          std::size_t rays_per_packet = 0) {
    std::size_t ties = 0;
    for_each_packet_arch([&]<class Arch>() {
        constexpr int width = int(RayPacket<Arch>::width);
        for (const PacketComparison& result :
             {compare_packets<Arch, 0, Test, Slabs>(bvh, mesh, rays, rays_per_packet, off),
              compare_packets<Arch, bvh::single_ray_lanes(width), Test, Slabs>(bvh, mesh, rays, rays_per_packet, off),
              compare_packets<Arch, width, Test, Slabs>(bvh, mesh, rays, rays_per_packet, off)}) {
            CHECK(result.hits > 0);
            result.require_agreement();
            ties += result.ties;
        }
    });
    return ties;
}

/// Primary rays of `blocks` pixel blocks, `block_w` x `block_h` pixels each, of a 640 x 360 image
/// of the camera, computed as ../shared/BENCHMARK.md writes them; a block's rays are consecutive,
/// row by row. The first block sits at the image centre, the others at random.
std::vector<Ray> pixel_block_rays(const CameraSpec& camera, int block_w, int block_h, std::size_t blocks,
                                  std::uint32_t seed) {
    constexpr int width = 640, height = 360;
    constexpr float kPi = 3.14159265358979f;
    const Vec3f forward = normalize(camera.target - camera.eye);
    const Vec3f right = normalize(cross(forward, camera.up));
    const Vec3f up = cross(right, forward);
    const float ty = std::tan(camera.fov_y_deg * kPi / 360.0f), tx = ty * float(width) / float(height);
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> column(0, width - block_w), row(0, height - block_h);
    std::vector<Ray> rays;
    for (std::size_t b = 0; b < blocks; ++b) {
        const int x0 = b == 0 ? (width - block_w) / 2 : column(rng), y0 = b == 0 ? (height - block_h) / 2 : row(rng);
        for (int y = y0; y < y0 + block_h; ++y)
            for (int x = x0; x < x0 + block_w; ++x) {
                const float sx = (2.0f * (float(x) + 0.5f) / float(width) - 1.0f) * tx;
                const float sy = (1.0f - 2.0f * (float(y) + 0.5f) / float(height)) * ty;
                rays.push_back({camera.eye, normalize(forward + sx * right + sy * up)});
            }
    }
    return rays;
}

/// Rays from `origin` whose direction components take every sign, +0 and -0 included, cycling so
/// that each packet holds lanes of several octants.
std::vector<Ray> rays_of_every_sign(const Vec3f& origin, std::size_t count, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> magnitude(0.05f, 1.0f);
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < count; ++i) {
        Vec3f d;
        for (int axis = 0; axis < 3; ++axis) {
            const std::size_t choice = (i >> (2 * axis)) % 4;  // positive, negative, +0, -0
            d[axis] = choice == 0 ? magnitude(rng) : choice == 1 ? -magnitude(rng) : choice == 2 ? 0.0f : -0.0f;
        }
        if (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f) d.x = -1.0f;
        rays.push_back({origin, d});  // not normalized: zero components keep their sign
    }
    return rays;
}

/// A lattice of unit right triangles in the planes x = i, y = j and z = k (as in
/// test_bvh_traversal.cpp): node boxes with integer planes, triangles sharing edges.
Mesh axis_lattice() {
    Mesh mesh;
    auto tri = [&](Vec3f p, Vec3f q, Vec3f r) {
        mesh.add_triangle(mesh.add_vertex(p), mesh.add_vertex(q), mesh.add_vertex(r));
    };
    for (int i = 0; i <= 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 4; ++k) {
                const float a = float(i), b = float(j), c = float(k);
                tri({a, b, c}, {a, b + 1, c}, {a, b, c + 1});
                tri({b, a, c}, {b, a, c + 1}, {b + 1, a, c});
                tri({b, c, a}, {b + 1, c, a}, {b, c + 1, a});
            }
    return mesh;
}

/// Axis-parallel rays starting on the lattice's planes (half-integer steps) with +0 and -0 in the
/// other components, several tmin; consecutive rays share their direction.
std::vector<Ray> rays_on_lattice_planes() {
    std::vector<Ray> rays;
    for (int axis = 0; axis < 3; ++axis)
        for (float sign : {1.0f, -1.0f})
            for (float zero : {0.0f, -0.0f})
                for (float tmin : {0.0f, 2.5f})
                    for (int u = 0; u <= 8; ++u)
                        for (int v = 0; v <= 8; ++v) {
                            Ray ray;
                            ray.dir = Vec3f{zero, zero, zero};
                            ray.dir[axis] = sign;
                            ray.origin[axis] = sign > 0 ? -1.0f : 5.0f;
                            ray.origin[(axis + 1) % 3] = 0.5f * float(u);
                            ray.origin[(axis + 2) % 3] = 0.5f * float(v);
                            ray.tmin = tmin;
                            rays.push_back(ray);
                        }
    return rays;
}

/// Rays from random points inside the box in random directions, with random [tmin, tmax] windows.
std::vector<Ray> windowed_rays_from_inside(const Aabb& box, std::size_t count, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), sym(-1.0f, 1.0f);
    const Vec3f extent = box.extent();
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < count; ++i) {
        Ray ray;
        ray.origin = box.lo + Vec3f{unit(rng) * extent.x, unit(rng) * extent.y, unit(rng) * extent.z};
        ray.dir = normalize(Vec3f{sym(rng), sym(rng), sym(rng)});
        ray.tmin = unit(rng) * 0.5f;
        ray.tmax = i % 3 == 0 ? kInfinity : ray.tmin + unit(rng) * 2.0f;
        rays.push_back(ray);
    }
    return rays;
}

}  // namespace

TEST_CASE("packets of incoherent rays find the single-ray hits at every width, for every builder setting") {
    BvhOptions sweep;
    sweep.builder = BvhBuilder::sweep_sah;
    BvhOptions one_per_leaf;
    one_per_leaf.max_leaf_size = 1;
    const Mesh mesh = random_soup(600, 11, 0.15f);
    const std::vector<Ray> rays = random_rays(mesh.bounds(), 400, 12);  // one in five axis-parallel
    for (const BvhOptions& options : {BvhOptions{}, BvhOptions::study(), sweep, one_per_leaf}) {
        CAPTURE(options.max_leaf_size);
        CAPTURE(to_string(options.builder));
        check_packets(Bvh::build(mesh, options), mesh, rays);
    }
    // The same rays grouped differently.
    std::vector<Ray> shuffled = rays;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(13));
    check_packets(Bvh::build(mesh), mesh, shuffled);
}

TEST_CASE("packets with the Möller-Trumbore test find its single-ray hits") {
    const Mesh mesh = random_soup(600, 21, 0.15f);
    check_packets<TriangleTest::moller_trumbore>(Bvh::build(mesh), mesh, random_rays(mesh.bounds(), 400, 22));
}

TEST_CASE("packets with the fast slab test find its single-ray hits, axis-parallel rays included") {
    const Mesh soup = random_soup(600, 23, 0.15f);
    check_packets<TriangleTest::watertight, SlabTest::fast>(Bvh::build(soup), soup,
                                                            random_rays(soup.bounds(), 400, 24));
    check_packets<TriangleTest::moller_trumbore, SlabTest::fast>(Bvh::build(soup), soup,
                                                                 rays_of_every_sign({0.05f, -0.1f, 0.2f}, 640, 25));
    const Mesh lattice = axis_lattice();
    check_packets<TriangleTest::watertight, SlabTest::fast>(Bvh::build(lattice), lattice, rays_on_lattice_planes());
}

TEST_CASE("mixed-sign packets, +0 and -0 included, find the single-ray hits") {
    const Mesh mesh = random_soup(600, 41, 0.12f);
    const Bvh bvh = Bvh::build(mesh);
    for (const Vec3f& origin : {Vec3f{0.05f, -0.1f, 0.2f}, Vec3f{-3.0f, 0.4f, 0.1f}}) {
        CAPTURE(origin.x);
        check_packets(bvh, mesh, rays_of_every_sign(origin, 640, 42));
    }
}

TEST_CASE("packets of axis-parallel rays starting on box planes, through shared edges, find the single-ray hits") {
    const Mesh mesh = axis_lattice();
    const std::vector<Ray> rays = rays_on_lattice_planes();
    std::vector<Ray> shuffled = rays;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(5));
    std::size_t shuffled_ties = 0;
    for (const int max_leaf : {1, 8}) {
        CAPTURE(max_leaf);
        BvhOptions options;
        options.max_leaf_size = max_leaf;
        const Bvh bvh = Bvh::build(mesh, options);
        check_packets(bvh, mesh, rays);
        shuffled_ties += check_packets(bvh, mesh, shuffled);
    }
    // Grouped at random, packets mix directions, and some lanes meet two edge-sharing triangles
    // at their t in the other order than alone: the tie allowance is exercised.
    CHECK(shuffled_ties > 0);
}

TEST_CASE("packets of rays from inside the scene with tmin/tmax windows find the single-ray hits") {
    const Mesh mesh = random_soup(600, 61, 0.15f);
    check_packets(Bvh::build(mesh), mesh, windowed_rays_from_inside(mesh.bounds(), 600, 62));
}

TEST_CASE("lanes switched off or with an empty window come back untouched and are never occluded") {
    const Mesh mesh = random_soup(500, 51, 0.15f);
    const Bvh bvh = Bvh::build(mesh);
    std::vector<Ray> rays = random_rays(mesh.bounds(), 400, 52);
    for (std::size_t i = 0; i < rays.size(); i += 7) {  // empty windows
        rays[i].tmin = 2.0f;
        rays[i].tmax = 1.0f;
    }
    SUBCASE("every third lane switched off") {
        check_packets(bvh, mesh, rays, [](std::size_t lane) { return lane % 3 == 1; });
    }
    SUBCASE("all lanes but one switched off") {
        check_packets(bvh, mesh, rays, [](std::size_t lane) { return lane != 2; });
    }
    SUBCASE("every lane switched off") {
        for_each_packet_arch([&]<class Arch>() {
            const PacketComparison result =
                compare_packets<Arch, 0>(bvh, mesh, rays, 0, [](std::size_t) { return true; });
            CHECK(result.lanes == 0);
            CHECK(result.untouched == 0);
            CHECK(result.padding == 0);
        });
    }
    SUBCASE("partial packets: fewer rays than lanes") {
        for_each_packet_arch([&]<class Arch>() {
            for (std::size_t count = 1; count < RayPacket<Arch>::width; count += 3) {
                CAPTURE(count);
                check_packets(bvh, mesh, rays, {}, count);
            }
        });
    }
}

TEST_CASE("an empty BVH leaves every lane a miss and occludes nothing") {
    const Mesh mesh;
    const Bvh bvh = Bvh::build(mesh);
    const std::vector<Ray> rays = random_rays({{-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f}}, 16, 81);
    for_each_packet_arch([&]<class Arch>() {
        const PacketComparison result = compare_packets<Arch, 0>(bvh, mesh, rays);
        CHECK(result.lanes == rays.size());
        CHECK(result.hits == 0);
        result.require_agreement();
    });
}

TEST_CASE(
    "camera pixel blocks of every built-in scene (2x2, 4x2, 4x4) and random camera rays find the single-ray hits") {
    for (const BuiltinSceneInfo& info : builtin_scenes()) {
        CAPTURE(info.name);
        const Scene& scene = builtin_scene(info.name);
        const Bvh& bvh = builtin_bvh(info.name);
        for_each_packet_arch([&]<class Arch>() {
            constexpr int width = int(RayPacket<Arch>::width);
            const auto [block_w, block_h] = packet_block(width);
            const std::vector<Ray> blocks = pixel_block_rays(scene.camera, block_w, block_h, 40, 91);
            const std::vector<Ray> random = camera_rays(scene.camera, 160, 92);
            for (const std::span<const Ray> rays : {std::span<const Ray>(blocks), std::span<const Ray>(random)}) {
                for (const PacketComparison& result :
                     {compare_packets<Arch, 0>(bvh, scene.mesh, rays),
                      compare_packets<Arch, bvh::single_ray_lanes(width)>(bvh, scene.mesh, rays)}) {
                    CHECK(result.hits > 0);
                    result.require_agreement();
                }
            }
        });
    }
}

TEST_CASE("the counters count per packet: at least the busiest lane's work, at most all lanes' together") {
    const Scene& scene = builtin_scene("teapot");
    const Bvh& bvh = builtin_bvh("teapot");
    for_each_packet_arch([&]<class Arch>() {
        constexpr std::size_t width = RayPacket<Arch>::width;
        const auto [block_w, block_h] = packet_block(width);
        const std::vector<Ray> rays = pixel_block_rays(scene.camera, block_w, block_h, 60, 101);
        std::size_t below_busiest = 0, above_sum = 0, shared_packets = 0;
        TraversalCounters packets, lanes;
        for (std::size_t first = 0; first < rays.size(); first += width) {
            const std::span<const Ray> chunk = std::span(rays).subspan(first, width);
            if (!lanes_share_octant(chunk, std::vector<bool>(width, true))) continue;  // others may visit more
            const RayPacket<Arch> packet(chunk);
            ++shared_packets;
            HitPacket<Arch> hits(packet);
            TraversalCounters one_packet, busiest, sum;
            bvh.intersect<TriangleTest::watertight, SlabTest::robust, Arch, TraversalCounters, 0>(packet, hits,
                                                                                                  one_packet);
            for (const Ray& ray : chunk) {
                TraversalCounters one_ray;
                bvh.intersect<TriangleTest::watertight>(ray, one_ray);
                busiest.nodes_visited = std::max(busiest.nodes_visited, one_ray.nodes_visited);
                busiest.triangles_tested = std::max(busiest.triangles_tested, one_ray.triangles_tested);
                sum += one_ray;
            }
            below_busiest += one_packet.nodes_visited < busiest.nodes_visited ||
                             one_packet.triangles_tested < busiest.triangles_tested;
            above_sum +=
                one_packet.nodes_visited > sum.nodes_visited || one_packet.triangles_tested > sum.triangles_tested;
            packets += one_packet;
            lanes += sum;
        }
        CHECK(shared_packets > 40);
        CHECK(below_busiest == 0);
        CHECK(above_sum == 0);
        // Coherent packets share most of their lanes' work.
        CHECK(packets.nodes_visited * 2 < lanes.nodes_visited);
    });
}

TEST_CASE("an any-hit packet stops each lane at its first hit: no more triangle tests than closest hit") {
    const Scene& scene = builtin_scene("hall");
    const Bvh& bvh = builtin_bvh("hall");
    for_each_packet_arch([&]<class Arch>() {
        constexpr std::size_t width = RayPacket<Arch>::width;
        const auto [block_w, block_h] = packet_block(width);
        const std::vector<Ray> rays = pixel_block_rays(scene.camera, block_w, block_h, 40, 111);
        TraversalCounters closest, any;
        for (std::size_t first = 0; first < rays.size(); first += width) {
            const RayPacket<Arch> packet(std::span<const Ray>(rays).subspan(first, width));
            HitPacket<Arch> hits(packet);
            bvh.intersect<TriangleTest::watertight, SlabTest::robust, Arch, TraversalCounters, 0>(packet, hits,
                                                                                                  closest);
            bvh.occluded<TriangleTest::watertight, SlabTest::robust, Arch, TraversalCounters, 0>(packet, any);
        }
        CHECK(any.triangles_tested < closest.triangles_tested);
        CHECK(any.nodes_visited < closest.nodes_visited);
    });
}
