// The triangle tests instantiated over xsimd batches give, lane by lane, the scalar
// TriangleIntersector's answer bit for bit: same hit or miss, same t, u and v bits.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "core/intersect_triangle.h"
#include "each_arch.h"
#include "simd/packet.h"
#include "support/random_scenes.h"

using namespace trident;
using trident::testing::for_each_packet_arch;

namespace {

struct Case {
    std::vector<Ray> rays;
    std::vector<Triangle> triangles;
};

/// Random triangles of mixed sizes with random rays (every fifth axis-parallel, with +0 and -0).
Case random_case(std::uint32_t seed) {
    Case c;
    for (const float size : {0.05f, 0.3f, 1.0f}) {
        const Mesh soup = testing::random_soup(100, seed, size);
        for (std::size_t i = 0; i < soup.triangle_count(); ++i) c.triangles.push_back(triangle_of(soup, i));
        ++seed;
    }
    c.rays = testing::random_rays(Aabb{{-1.2f, -1.2f, -1.2f}, {1.2f, 1.2f, 1.2f}}, 1000, seed);
    return c;
}

/// Rays aimed at each triangle's corners, edge midpoints, centroid and points just outside, from
/// random directions, with random tmin and tmax around the hit: hits, edge hits and near misses.
Case aimed_case(std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> sym(-1.0f, 1.0f), unit(0.0f, 1.0f);
    const Mesh soup = testing::random_soup(150, seed, 0.3f);
    Case c;
    for (std::size_t i = 0; i < soup.triangle_count(); ++i) {
        const Triangle tri = triangle_of(soup, i);
        c.triangles.push_back(tri);
        const Vec3f targets[] = {tri.a,
                                 tri.b,
                                 tri.c,
                                 (tri.a + tri.b) * 0.5f,
                                 (tri.b + tri.c) * 0.5f,
                                 (tri.c + tri.a) * 0.5f,
                                 tri.centroid(),
                                 tri.a * 1.01f - tri.centroid() * 0.01f};
        for (const Vec3f& target : targets) {
            Vec3f d{sym(rng), sym(rng), sym(rng)};
            if (dot(d, d) < 1e-4f) d = {0.0f, 0.0f, 1.0f};
            Ray ray{target - d * 2.0f, d};
            const float r = unit(rng);  // a quarter of the rays have the hit outside [tmin, tmax)
            ray.tmin = r < 0.125f ? 2.5f : (r < 0.5f ? 0.5f : 0.0f);
            ray.tmax = r > 0.875f ? 1.5f : (r > 0.5f ? 2.0f + unit(rng) : kInfinity);
            c.rays.push_back(ray);
        }
    }
    return c;
}

/// Axis-aligned triangles with dyadic corners, both windings, and axis-parallel rays (+0 and -0
/// in the other components) through their corners, edges and interiors: edge functions are
/// exactly zero here, which sends the watertight test to its double-precision fallback.
Case axis_aligned_case() {
    Case c;
    for (int axis = 0; axis < 3; ++axis) {
        const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
        auto point = [&](float s, float t, float h) {
            Vec3f p;
            p[axis] = h;
            p[a1] = s;
            p[a2] = t;
            return p;
        };
        for (const float h : {0.0f, 0.5f}) {
            const Vec3f p00 = point(0, 0, h), p10 = point(1, 0, h), p01 = point(0, 1, h), p11 = point(1, 1, h);
            c.triangles.push_back({p00, p10, p01});
            c.triangles.push_back({p10, p11, p01});
            c.triangles.push_back({p00, p01, p10});  // the first, facing the other way
        }
        for (const float s : {0.0f, 0.25f, 0.5f, 1.0f, 1.5f})
            for (const float t : {0.0f, 0.5f, 0.75f, 1.0f})
                for (const float sign : {1.0f, -1.0f})
                    for (const float zero : {0.0f, -0.0f}) {
                        Ray ray{point(s, t, -2.0f * sign), Vec3f{zero, zero, zero}};
                        ray.dir[axis] = sign;
                        c.rays.push_back(ray);
                    }
    }
    return c;
}

/// Degenerate triangles (a point, two equal corners, collinear corners) and rays lying in a
/// triangle's plane: the det == 0 paths.
Case degenerate_case() {
    Case c;
    const Vec3f p{0.1f, 0.2f, 0.3f}, q{0.7f, -0.1f, 0.4f}, r{0.3f, 0.5f, -0.2f};
    c.triangles = {{p, p, p}, {p, p, q}, {p, q, p}, {p, q, (p + q) * 0.5f}, {p, q, q * 2.0f - p}, {p, q, r}};
    const Vec3f in_plane = q - p, normal = cross(q - p, r - p);
    c.rays = {{p - in_plane, in_plane},
              {p - in_plane * 0.5f, in_plane * 0.5f},
              {(p + q + r) * (1.0f / 3.0f) + normal, -normal},
              {p + normal, -normal},
              {q - normal, normal},
              {p - (r - p), r - p}};
    return c;
}

struct Mismatches {
    std::size_t lanes = 0, hits = 0, hit_on_edge = 0, wrong = 0;
    std::size_t uniform_packets = 0;  // packets whose lanes all permute the axes alike (the fast path)
    std::string first;

    void note(const std::string& what) {
        ++wrong;
        if (first.empty()) first = what;
    }
};

void compare_lane(bool scalar_hit, const TriangleHit& scalar, bool packet_hit, float t, float u, float v,
                  const std::string& where, Mismatches& m) {
    ++m.lanes;
    if (scalar_hit != packet_hit) return m.note("hit/miss differs " + where);
    if (!scalar_hit) return;
    ++m.hits;
    if (scalar.u == 0.0f || scalar.v == 0.0f) ++m.hit_on_edge;
    if (std::bit_cast<std::uint32_t>(scalar.t) != std::bit_cast<std::uint32_t>(t) ||
        std::bit_cast<std::uint32_t>(scalar.u) != std::bit_cast<std::uint32_t>(u) ||
        std::bit_cast<std::uint32_t>(scalar.v) != std::bit_cast<std::uint32_t>(v))
        m.note("t/u/v bits differ " + where);
}

/// Rays in packets of the arch's width (the last one partial), each triangle broadcast to all lanes.
template <class Arch, TriangleTest Test>
void compare_ray_packets(const Case& c, Mismatches& m) {
    using Float = xsimd::batch<float, Arch>;
    using L = Lanes<Float>;
    constexpr std::size_t width = Float::size;
    const std::span<const Ray> rays(c.rays);
    for (std::size_t first = 0; first < rays.size(); first += width) {
        const auto chunk = rays.subspan(first, std::min(width, rays.size() - first));
        const RayPacket<Arch> packet(chunk);
        const auto packet_test = packet_intersector<Test>(packet);
        m.uniform_packets += L::major_axis_to_z(packet.dir).uniform;
        for (std::size_t k = 0; k < c.triangles.size(); ++k) {
            TriangleHitT<Float> out{};
            const std::uint32_t hit_bits = L::bits(packet_test.intersect(c.triangles[k], packet.tmax, out));
            if ((hit_bits & ~L::bits(packet.active)) != 0) m.note("an inactive lane hit");
            const auto t = L::to_array(out.t), u = L::to_array(out.u), v = L::to_array(out.v);
            for (std::size_t i = 0; i < chunk.size(); ++i) {
                TriangleHit h{};
                const bool scalar_hit = TriangleIntersector<Test>(chunk[i]).intersect(c.triangles[k], chunk[i].tmax, h);
                compare_lane(scalar_hit, h, (hit_bits >> i) & 1u, t[i], u[i], v[i],
                             "(ray " + std::to_string(first + i) + ", triangle " + std::to_string(k) + ")", m);
            }
        }
    }
}

/// How a test of one ray against a triangle per lane is set up: from the ray broadcast to vectors,
/// with the corners as stored; or as the wide BVH sets it up (the scalar set-up broadcast, the
/// corners loaded in the ray's axes, its rare checks handed the corners as stored; watertight only).
enum class OneRaySetUp { broadcast_ray, scalar_in_ray_axes };

/// One ray broadcast to all lanes against a different triangle per lane (the leaf-wide layout).
template <class Arch, TriangleTest Test, OneRaySetUp SetUp = OneRaySetUp::broadcast_ray>
void compare_triangle_packets(const Case& c, Mismatches& m) {
    using Float = xsimd::batch<float, Arch>;
    using L = Lanes<Float>;
    constexpr std::size_t width = Float::size;
    constexpr std::array<int, 3> kAsStored{0, 1, 2};
    for (std::size_t r = 0; r < c.rays.size(); ++r) {
        const Ray& ray = c.rays[r];
        const TriangleIntersector<Test> scalar_test(ray);
        const auto packet_test = [&] {
            if constexpr (SetUp == OneRaySetUp::scalar_in_ray_axes)
                return TriangleIntersectorT<Test, Float>(scalar_test);
            else
                return TriangleIntersectorT<Test, Float>(Vec3T<Float>(ray.origin), Vec3T<Float>(ray.dir),
                                                         Float(ray.tmin));
        }();
        for (std::size_t first = 0; first < c.triangles.size(); first += width) {
            const std::size_t count = std::min(width, c.triangles.size() - first);
            // Corner k of the lanes' triangles, its components from the rows named (the last
            // triangle repeated past the end).
            auto corner = [&](int k, const std::array<int, 3>& rows) {
                Vec3T<Float> out;
                for (int i = 0; i < 3; ++i) {
                    typename L::Array lanes{};
                    for (std::size_t lane = 0; lane < width; ++lane) {
                        const Triangle& tri = c.triangles[first + std::min(lane, count - 1)];
                        lanes[lane] = (k == 0 ? tri.a : k == 1 ? tri.b : tri.c)[rows[std::size_t(i)]];
                    }
                    out[i] = L::from_array(lanes);
                }
                return out;
            };
            TriangleHitT<Float> out{};
            const auto hit = [&] {
                if constexpr (SetUp == OneRaySetUp::scalar_in_ray_axes) {
                    const std::array<int, 3> axes = packet_test.ray_axes();
                    const auto as_stored = [&] {
                        return std::array{corner(0, kAsStored), corner(1, kAsStored), corner(2, kAsStored)};
                    };
                    return packet_test.intersect_in_ray_axes(corner(0, axes), corner(1, axes), corner(2, axes),
                                                             Float(ray.tmax), out, as_stored);
                } else {
                    return packet_test.intersect(corner(0, kAsStored), corner(1, kAsStored), corner(2, kAsStored),
                                                 Float(ray.tmax), out);
                }
            }();
            const std::uint32_t hit_bits = L::bits(hit);
            const auto t = L::to_array(out.t), u = L::to_array(out.u), v = L::to_array(out.v);
            for (std::size_t i = 0; i < count; ++i) {
                TriangleHit h{};
                const bool scalar_hit = scalar_test.intersect(c.triangles[first + i], ray.tmax, h);
                compare_lane(scalar_hit, h, (hit_bits >> i) & 1u, t[i], u[i], v[i],
                             "(ray " + std::to_string(r) + ", triangle " + std::to_string(first + i) + ")", m);
            }
        }
    }
}

template <TriangleTest Test>
void check_all_widths_match_scalar(const Case& c, bool expect_edge_hits) {
    const std::string test_name = to_string(Test);
    CAPTURE(test_name);
    for_each_packet_arch([&]<class Arch>() {
        Mismatches rays, triangles;
        compare_ray_packets<Arch, Test>(c, rays);
        compare_triangle_packets<Arch, Test>(c, triangles);
        INFO("ray packets: ", rays.first, "; triangle packets: ", triangles.first);
        CHECK(rays.wrong == 0);
        CHECK(triangles.wrong == 0);
        CHECK(rays.lanes == c.rays.size() * c.triangles.size());
        CHECK(triangles.lanes == rays.lanes);
        CHECK(rays.hits > 0);
        if (expect_edge_hits) CHECK(rays.hit_on_edge > 0);
        if constexpr (Test == TriangleTest::watertight) {
            Mismatches in_ray_axes;
            compare_triangle_packets<Arch, Test, OneRaySetUp::scalar_in_ray_axes>(c, in_ray_axes);
            INFO("triangle packets in the ray's axes: ", in_ray_axes.first);
            CHECK(in_ray_axes.wrong == 0);
            CHECK(in_ray_axes.lanes == rays.lanes);
        }
    });
}

}  // namespace

TEST_CASE("packet triangle tests equal the scalar tests bit for bit on random rays and triangles") {
    const Case c = random_case(7);
    check_all_widths_match_scalar<TriangleTest::watertight>(c, false);
    check_all_widths_match_scalar<TriangleTest::moller_trumbore>(c, false);
}

TEST_CASE("packet triangle tests equal the scalar tests bit for bit on rays aimed at corners and edges") {
    const Case c = aimed_case(11);
    check_all_widths_match_scalar<TriangleTest::watertight>(c, false);
    check_all_widths_match_scalar<TriangleTest::moller_trumbore>(c, false);
}

TEST_CASE("packets whose rays share the watertight test's axis permutation equal the scalar tests bit for bit") {
    // Grouped by the permutation (as a coherent packet's rays are), the packets permute whole
    // vectors (AxisPermutation::uniform) instead of lanes; the random cases above mostly mix.
    Case c = aimed_case(13);
    auto permutation = [](const Ray& ray) {
        const auto axes = Lanes<float>::major_axis_to_z(ray.dir);
        return 9 * axes.kz + 3 * axes.kx + axes.ky;
    };
    std::stable_sort(c.rays.begin(), c.rays.end(),
                     [&](const Ray& a, const Ray& b) { return permutation(a) < permutation(b); });
    for_each_packet_arch([&]<class Arch>() {
        Mismatches m;
        compare_ray_packets<Arch, TriangleTest::watertight>(c, m);
        INFO(m.first);
        CHECK(m.wrong == 0);
        CHECK(m.hits > 0);
        CHECK(m.uniform_packets * 2 > c.rays.size() / xsimd::batch<float, Arch>::size);  // most of them
    });
}

TEST_CASE("packet watertight test takes the double fallback lane by lane exactly as the scalar test") {
    const Case c = axis_aligned_case();
    check_all_widths_match_scalar<TriangleTest::watertight>(c, true);
    check_all_widths_match_scalar<TriangleTest::moller_trumbore>(c, false);
}

TEST_CASE("packet triangle tests equal the scalar tests on degenerate triangles and rays in the plane") {
    const Case c = degenerate_case();
    check_all_widths_match_scalar<TriangleTest::watertight>(c, false);
    check_all_widths_match_scalar<TriangleTest::moller_trumbore>(c, false);
}
