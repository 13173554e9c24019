#include "bench/embree_baseline.h"

#if TRIDENT_HAVE_EMBREE

#include <fmt/format.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "bench/statistics.h"
#include "render/primary_packets.h"
#include "simd/mask.h"

namespace trident::bench {
namespace {

/// Pixels one packet call covers and the calls themselves, per width. Blocks are at most 4 pixels
/// wide so neighbouring lanes stay close in the image (coherent rays, as the context states).
template <int Width>
struct Packet;
template <>
struct Packet<4> {
    using Rays = RTCRay4;
    using RayHit = RTCRayHit4;
    static constexpr std::uint32_t block_w = 2, block_h = 2;
    static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* r) {
        rtcIntersect4(valid, s, c, r);
    }
    static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Rays* r) {
        rtcOccluded4(valid, s, c, r);
    }
};
template <>
struct Packet<8> {
    using Rays = RTCRay8;
    using RayHit = RTCRayHit8;
    static constexpr std::uint32_t block_w = 4, block_h = 2;
    static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* r) {
        rtcIntersect8(valid, s, c, r);
    }
    static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Rays* r) {
        rtcOccluded8(valid, s, c, r);
    }
};
template <>
struct Packet<16> {
    using Rays = RTCRay16;
    using RayHit = RTCRayHit16;
    static constexpr std::uint32_t block_w = 4, block_h = 4;
    static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* r) {
        rtcIntersect16(valid, s, c, r);
    }
    static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Rays* r) {
        rtcOccluded16(valid, s, c, r);
    }
};

constexpr std::uint32_t kTilePixels = 16;  // blocks are handed out in tiles of about 16x16 pixels, as ours

Hit to_hit(unsigned geom_id, unsigned prim_id, float t, float u, float v) {
    if (geom_id == RTC_INVALID_GEOMETRY_ID) return Hit{};
    return Hit{TriangleId(prim_id), t, u, v};
}

/// Embree's single ray for ours (all masks on).
RTCRay to_embree(const Ray& ray) {
    RTCRay r{};
    r.org_x = ray.origin.x, r.org_y = ray.origin.y, r.org_z = ray.origin.z;
    r.dir_x = ray.dir.x, r.dir_y = ray.dir.y, r.dir_z = ray.dir.z;
    r.tnear = ray.tmin;
    r.tfar = ray.tmax;
    r.mask = ~0u;
    return r;
}

/// Lane `lane` of Embree's packet of rays (RTCRay4/8/16) set to ours.
template <class Rays>
void set_lane(Rays& r, int lane, const Ray& ray) {
    r.org_x[lane] = ray.origin.x, r.org_y[lane] = ray.origin.y, r.org_z[lane] = ray.origin.z;
    r.dir_x[lane] = ray.dir.x, r.dir_y[lane] = ray.dir.y, r.dir_z[lane] = ray.dir.z;
    r.tnear[lane] = ray.tmin;
    r.tfar[lane] = ray.tmax;
    r.mask[lane] = ~0u;
}

/// rtcIntersect1 of one ray, as our Hit.
Hit intersect_one(RTCScene scene, RTCIntersectContext& context, const Ray& ray) {
    RTCRayHit rayhit{};
    rayhit.ray = to_embree(ray);
    rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &rayhit);
    return to_hit(rayhit.hit.geomID, rayhit.hit.primID, rayhit.ray.tfar, rayhit.hit.u, rayhit.hit.v);
}

RTCIntersectContext coherent_context() {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    return context;
}

/// Calls per_block(bx, by) for every block_w x block_h block of the image, in parallel tiles.
template <class PerBlock>
void for_each_block(const Camera& camera, std::uint32_t block_w, std::uint32_t block_h, PerBlock&& per_block) {
    const std::uint32_t blocks_x = (camera.width() + block_w - 1) / block_w;
    const std::uint32_t blocks_y = (camera.height() + block_h - 1) / block_h;
    const tbb::blocked_range2d<std::uint32_t> blocks(0, blocks_y, kTilePixels / block_h, 0, blocks_x,
                                                     kTilePixels / block_w);
    tbb::parallel_for(blocks, [&](const tbb::blocked_range2d<std::uint32_t>& tile) {
        for (std::uint32_t by = tile.rows().begin(); by != tile.rows().end(); ++by)
            for (std::uint32_t bx = tile.cols().begin(); bx != tile.cols().end(); ++bx) per_block(bx, by);
    });
}

void trace_single(RTCScene scene, const Camera& camera, std::span<Hit> hits) {
    for_each_block(camera, 1, 1, [&](std::uint32_t x, std::uint32_t y) {
        RTCIntersectContext context = coherent_context();
        hits[std::size_t(y) * camera.width() + x] = intersect_one(scene, context, camera.primary_ray(x, y));
    });
}

template <int Width>
void trace_packets(RTCScene scene, const Camera& camera, std::span<Hit> hits) {
    using P = Packet<Width>;
    using Batch = xsimd::make_sized_batch_t<float, Width>;  // void where the CPU has no such width
    const ImageTile image{0, 0, camera.width(), camera.height()};
    for_each_block(camera, P::block_w, P::block_h, [&](std::uint32_t bx, std::uint32_t by) {
        RTCIntersectContext context = coherent_context();
        alignas(64) int valid[Width];
        alignas(64) typename P::RayHit rayhit{};
        if constexpr (!std::is_void_v<Batch>) {
            // The rays made in SIMD as our packets make them (render/primary_packets.h), the same
            // rays at the same cost.
            static_assert(P::block_w == PrimaryBlock<typename Batch::arch_type>::kBlockWidth);
            const PrimaryBlock<typename Batch::arch_type> block(camera, image, bx * P::block_w, by * P::block_h);
            block.dir.x.store_aligned(rayhit.ray.dir_x);
            block.dir.y.store_aligned(rayhit.ray.dir_y);
            block.dir.z.store_aligned(rayhit.ray.dir_z);
            Batch(block.origin.x).store_aligned(rayhit.ray.org_x);
            Batch(block.origin.y).store_aligned(rayhit.ray.org_y);
            Batch(block.origin.z).store_aligned(rayhit.ray.org_z);
            Batch(0.0f).store_aligned(rayhit.ray.tnear);
            Batch(kInfinity).store_aligned(rayhit.ray.tfar);
            const std::uint32_t active = simd::mask_bits(block.active);
            for (int lane = 0; lane < Width; ++lane) {
                valid[lane] = (active >> lane & 1u) ? -1 : 0;
                rayhit.ray.mask[lane] = ~0u;
                rayhit.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
            }
        } else {
            for (int lane = 0; lane < Width; ++lane) {
                const std::uint32_t x = bx * P::block_w + std::uint32_t(lane) % P::block_w;
                const std::uint32_t y = by * P::block_h + std::uint32_t(lane) / P::block_w;
                valid[lane] = x < camera.width() && y < camera.height() ? -1 : 0;
                rayhit.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
                if (!valid[lane]) continue;
                set_lane(rayhit.ray, lane, camera.primary_ray(x, y));
            }
        }
        P::intersect(valid, scene, &context, &rayhit);
        for (int lane = 0; lane < Width; ++lane) {
            if (!valid[lane]) continue;
            const std::uint32_t x = bx * P::block_w + std::uint32_t(lane) % P::block_w;
            const std::uint32_t y = by * P::block_h + std::uint32_t(lane) / P::block_w;
            hits[std::size_t(y) * camera.width() + x] =
                to_hit(rayhit.hit.geomID[lane], rayhit.hit.primID[lane], rayhit.ray.tfar[lane], rayhit.hit.u[lane],
                       rayhit.hit.v[lane]);
        }
    });
}

/// The camera's rays in 8x8 pixel blocks, one rtcIntersect1M call per block (Embree's stream path).
void trace_stream_blocks(RTCScene scene, const Camera& camera, std::span<Hit> hits) {
    constexpr std::uint32_t kBlock = kEmbreeStreamBlock;
    for_each_block(camera, kBlock, kBlock, [&](std::uint32_t bx, std::uint32_t by) {
        RTCIntersectContext context = coherent_context();
        std::array<RTCRayHit, kBlock * kBlock> rayhits;
        std::array<std::size_t, kBlock * kBlock> pixel;
        unsigned rays = 0;
        for (std::uint32_t y = by * kBlock; y < std::min((by + 1) * kBlock, camera.height()); ++y)
            for (std::uint32_t x = bx * kBlock; x < std::min((bx + 1) * kBlock, camera.width()); ++x) {
                rayhits[rays].ray = to_embree(camera.primary_ray(x, y));
                rayhits[rays].hit.geomID = RTC_INVALID_GEOMETRY_ID;
                pixel[rays++] = std::size_t(y) * camera.width() + x;
            }
        rtcIntersect1M(scene, &context, rayhits.data(), rays, sizeof(RTCRayHit));
        for (unsigned i = 0; i < rays; ++i) {
            const RTCRayHit& r = rayhits[i];
            hits[pixel[i]] = to_hit(r.hit.geomID, r.hit.primID, r.ray.tfar, r.hit.u, r.hit.v);
        }
    });
}

// ---- Secondary rays (issue 9): a list of rays, any-hit or closest hit -------------------------

/// Writes one result per ray: the any-hit bit or the closest hit.
template <bool AnyHit>
using Result = std::conditional_t<AnyHit, std::uint8_t, Hit>;

/// Rays kept in primary-packet order are coherent; rays regrouped by octant are not.
RTCIntersectContext stream_context(PacketGrouping grouping) {
    RTCIntersectContext context = coherent_context();
    if (grouping == PacketGrouping::by_octant) context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    return context;
}

/// rtcOccluded1 or rtcIntersect1 per ray; Embree marks an occluded ray by setting tfar to -inf.
template <bool AnyHit>
void trace_single_rays(RTCScene scene, std::span<const Ray> rays, PacketGrouping grouping,
                       std::span<Result<AnyHit>> out) {
    for_each_stream_chunk(rays.size(), [&](std::size_t first, std::size_t last) {
        RTCIntersectContext context = stream_context(grouping);
        for (std::size_t i = first; i != last; ++i) {
            if (!is_traced(rays[i])) {
                out[i] = Result<AnyHit>{};
            } else if constexpr (AnyHit) {
                RTCRay r = to_embree(rays[i]);
                rtcOccluded1(scene, &context, &r);
                out[i] = r.tfar < 0.0f;
            } else {
                out[i] = intersect_one(scene, context, rays[i]);
            }
        }
    });
}

/// rtcOccludedN or rtcIntersectN on the packets our traversals make of the same rays
/// (for_each_stream_packet over the same chunks), lanes past a short packet's end off.
template <int Width, bool AnyHit>
void trace_ray_packets(RTCScene scene, std::span<const Ray> rays, PacketGrouping grouping,
                       std::span<Result<AnyHit>> out) {
    using P = Packet<Width>;
    for_each_stream_chunk(rays.size(), [&](std::size_t first, std::size_t last) {
        RTCIntersectContext context = stream_context(grouping);
        const std::span<const Ray> chunk = rays.subspan(first, last - first);
        for (std::size_t i = 0; i < chunk.size(); ++i)
            if (!is_traced(chunk[i])) out[first + i] = Result<AnyHit>{};
        for_each_stream_packet(chunk, Width, grouping, [&](std::span<const std::size_t> index) {
            alignas(64) int valid[Width];
            alignas(64) std::conditional_t<AnyHit, typename P::Rays, typename P::RayHit> packet{};
            auto& packet_rays = [&]() -> auto& {
                if constexpr (AnyHit)
                    return packet;
                else
                    return packet.ray;
            }
            ();
            for (int lane = 0; lane < Width; ++lane) {
                valid[lane] = std::size_t(lane) < index.size() ? -1 : 0;
                if constexpr (!AnyHit) packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
                if (valid[lane]) set_lane(packet_rays, lane, chunk[index[std::size_t(lane)]]);
            }
            if constexpr (AnyHit)
                P::occluded(valid, scene, &context, &packet);
            else
                P::intersect(valid, scene, &context, &packet);
            for (std::size_t lane = 0; lane < index.size(); ++lane) {
                if constexpr (AnyHit)
                    out[first + index[lane]] = packet.tfar[lane] < 0.0f;
                else
                    out[first + index[lane]] = to_hit(packet.hit.geomID[lane], packet.hit.primID[lane],
                                                      packet.ray.tfar[lane], packet.hit.u[lane], packet.hit.v[lane]);
            }
        });
    });
}

/// Calls f(std::integral_constant<int, W>{}) for Embree's call widths 1, 4, 8 and 16.
template <class F>
void with_embree_width(int packet_width, F&& f) {
    switch (packet_width) {
        case 1:
            return f(std::integral_constant<int, 1>{});
        case 4:
            return f(std::integral_constant<int, 4>{});
        case 8:
            return f(std::integral_constant<int, 8>{});
        case 16:
            return f(std::integral_constant<int, 16>{});
    }
    throw std::invalid_argument(fmt::format("Embree has no packet width {}", packet_width));
}

/// Calls trace_single_rays or trace_ray_packets of the width for AnyHit's results.
template <bool AnyHit>
void trace_rays(RTCScene scene, std::span<const Ray> rays, int packet_width, PacketGrouping grouping,
                std::span<Result<AnyHit>> out) {
    with_embree_width(packet_width, [&](auto width) {
        if constexpr (width == 1)
            trace_single_rays<AnyHit>(scene, rays, grouping, out);
        else
            trace_ray_packets<width, AnyHit>(scene, rays, grouping, out);
    });
}

}  // namespace

EmbreeDevice::EmbreeDevice(int threads, EmbreeIsa isa) {
    std::string config = fmt::format("threads={},verbose=0", threads);
    if (isa != EmbreeIsa::native) config += fmt::format(",max_isa={}", to_string(isa));
    device_ = rtcNewDevice(config.c_str());
    if (!device_)
        throw std::runtime_error(
            fmt::format("embree: rtcNewDevice failed (error {})", int(rtcGetDeviceError(nullptr))));
    rtcSetDeviceMemoryMonitorFunction(device_, &EmbreeDevice::monitor_memory, this);
}

EmbreeDevice::~EmbreeDevice() { rtcReleaseDevice(device_); }

bool EmbreeDevice::monitor_memory(void* self, ssize_t bytes, bool) {
    static_cast<EmbreeDevice*>(self)->live_bytes_ += std::int64_t(bytes);
    return true;
}

void EmbreeDevice::throw_on_error(const char* what) const {
    const RTCError error = rtcGetDeviceError(device_);
    if (error != RTC_ERROR_NONE)
        throw std::runtime_error(fmt::format("embree: {} failed (error {})", what, int(error)));
}

EmbreeScene::EmbreeScene(const EmbreeDevice& device, const Mesh& mesh, EmbreeQuality quality) {
    const std::int64_t bytes_before = device.live_bytes();
    const auto start = std::chrono::steady_clock::now();
    scene_ = rtcNewScene(device.handle());
    device.throw_on_error("rtcNewScene");
    try {
        build(device, mesh, quality);
    } catch (...) {
        rtcReleaseScene(scene_);
        throw;
    }
    build_ms_ = ms_since(start);
    bytes_ = std::size_t(std::max<std::int64_t>(0, device.live_bytes() - bytes_before));
}

void EmbreeScene::build(const EmbreeDevice& device, const Mesh& mesh, EmbreeQuality quality) {
    const RTCBuildQuality rtc_quality = quality == EmbreeQuality::low      ? RTC_BUILD_QUALITY_LOW
                                        : quality == EmbreeQuality::medium ? RTC_BUILD_QUALITY_MEDIUM
                                                                           : RTC_BUILD_QUALITY_HIGH;
    rtcSetSceneBuildQuality(scene_, rtc_quality);
    RTCGeometry geometry = rtcNewGeometry(device.handle(), RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(geometry, rtc_quality);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), mesh.vertex_count()));
    auto* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), mesh.triangle_count()));
    device.throw_on_error("allocating the geometry buffers");
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
        vertices[3 * i] = mesh.x[i];
        vertices[3 * i + 1] = mesh.y[i];
        vertices[3 * i + 2] = mesh.z[i];
    }
    for (std::size_t i = 0; i < mesh.triangle_count(); ++i) {
        indices[3 * i] = mesh.triangles[i].v0;
        indices[3 * i + 1] = mesh.triangles[i].v1;
        indices[3 * i + 2] = mesh.triangles[i].v2;
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);  // the first geometry: geomID 0
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
    device.throw_on_error("building the scene");
}

EmbreeScene::~EmbreeScene() { rtcReleaseScene(scene_); }

void EmbreeScene::trace(const Camera& camera, int packet_width, std::span<Hit> hits) const {
    with_embree_width(packet_width, [&](auto width) {
        if constexpr (width == 1)
            trace_single(scene_, camera, hits);
        else
            trace_packets<width>(scene_, camera, hits);
    });
}

void EmbreeScene::trace_stream(const Camera& camera, std::span<Hit> hits) const {
    trace_stream_blocks(scene_, camera, hits);
}

void EmbreeScene::occluded(std::span<const Ray> rays, int packet_width, PacketGrouping grouping,
                           std::span<std::uint8_t> occluded) const {
    trace_rays<true>(scene_, rays, packet_width, grouping, occluded);
}

void EmbreeScene::intersect(std::span<const Ray> rays, int packet_width, PacketGrouping grouping,
                            std::span<Hit> hits) const {
    trace_rays<false>(scene_, rays, packet_width, grouping, hits);
}

}  // namespace trident::bench

#endif  // TRIDENT_HAVE_EMBREE
