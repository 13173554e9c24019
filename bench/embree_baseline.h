#pragma once
// Embree 3 as a baseline and as an independent reference tracer, on the same rays as ours.
// The mesh becomes one triangle geometry in file order, so Embree's primID is our triangle index;
// rays carry our normalized directions, so tfar is t along them. Compiled only when CMake found
// Embree (TRIDENT_HAVE_EMBREE); without it trident-bench runs everything else.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "bench/traversal.h"
#include "camera/camera.h"
#include "core/mesh.h"
#include "core/ray.h"
#include "render/stream_packets.h"

#if TRIDENT_HAVE_EMBREE
#include <embree3/rtcore.h>

#include <atomic>
#endif

namespace trident::bench {

#if TRIDENT_HAVE_EMBREE
inline constexpr bool kHaveEmbree = true;
#else
inline constexpr bool kHaveEmbree = false;
#endif

/// "rtcIntersect1", "rtcIntersect4", ...: the Embree call of a packet width (1: one ray).
inline std::string embree_call_name(int packet_width) { return "rtcIntersect" + std::to_string(packet_width); }
/// "rtcOccluded1", "rtcOccluded4", ...: the any-hit call of a packet width (shadow rays).
inline std::string embree_occluded_name(int packet_width) { return "rtcOccluded" + std::to_string(packet_width); }

/// The traversal name of Embree's stream row: rtcIntersect1M on 8x8 pixel blocks (primary rays).
inline constexpr const char* kEmbreeStreamName = "stream8x8";
/// Side of the pixel blocks one rtcIntersect1M call of the stream row takes.
inline constexpr std::uint32_t kEmbreeStreamBlock = 8;

/// The Embree row a row of ours is compared with, of the same width (one ray against one ray,
/// packets against packets): rtcOccluded1 / rtcOccludedN for shadow rays, else rtcIntersect1 /
/// rtcIntersectN.
inline std::string embree_counterpart(Traversal traversal, std::string_view ray_kind = "primary") {
    const int width = rays_per_call(traversal);
    return ray_kind == "shadow" ? embree_occluded_name(width) : embree_call_name(width);
}

/// Which of Embree's builders makes its BVH (`--embree-quality`). High, the default, is its best
/// tree (SAH with spatial splits), the baseline our traversals are held against; medium is its
/// binned SAH builder without spatial splits, the counterpart of our BVH's build; low is its Morton
/// code builder.
enum class EmbreeQuality { low, medium, high };

/// "RTC_BUILD_QUALITY_HIGH" and so on: Embree's name for the setting.
inline const char* to_string(EmbreeQuality quality) {
    switch (quality) {
        case EmbreeQuality::low:
            return "RTC_BUILD_QUALITY_LOW";
        case EmbreeQuality::medium:
            return "RTC_BUILD_QUALITY_MEDIUM";
        case EmbreeQuality::high:
            break;
    }
    return "RTC_BUILD_QUALITY_HIGH";
}
/// The most advanced instruction set Embree may pick its kernels from (`--embree-isa`): native
/// lets it choose (the best this CPU runs), the others go into rtcNewDevice's config as max_isa.
enum class EmbreeIsa { native, sse42, avx2, avx512 };

inline constexpr EmbreeIsa kAllEmbreeIsas[] = {EmbreeIsa::native, EmbreeIsa::sse42, EmbreeIsa::avx2, EmbreeIsa::avx512};

/// Embree's spelling of the ISA in its config string ("native": no limit given).
constexpr const char* to_string(EmbreeIsa isa) {
    switch (isa) {
        case EmbreeIsa::sse42:
            return "sse4.2";
        case EmbreeIsa::avx2:
            return "avx2";
        case EmbreeIsa::avx512:
            return "avx512";
        case EmbreeIsa::native:
            break;
    }
    return "native";
}

/// Whether this CPU runs the ISA's instructions (Embree's avx512 kernels need AVX-512 F, CD, DQ, BW, VL).
inline bool cpu_runs(EmbreeIsa isa) {
    switch (isa) {
        case EmbreeIsa::sse42:
            return __builtin_cpu_supports("sse4.2");
        case EmbreeIsa::avx2:
            return __builtin_cpu_supports("avx2");
        case EmbreeIsa::avx512:
            return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
                   __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
                   __builtin_cpu_supports("avx512vl");
        case EmbreeIsa::native:
            break;
    }
    return true;
}

/// How an Embree scene is built and traced, stated in every output beside its figures.
inline std::string embree_settings(EmbreeQuality quality, EmbreeIsa isa = EmbreeIsa::native) {
    return std::string(to_string(quality)) + ", default scene flags, coherent intersect context (incoherent for " +
           "diffuse rays), " +
           (isa == EmbreeIsa::native ? std::string("isa native") : "max_isa=" + std::string(to_string(isa)));
}

#if TRIDENT_HAVE_EMBREE

/// An Embree device with a fixed thread count ("threads=N") and, unless native, an ISA limit
/// ("max_isa=avx2"), that counts the bytes it holds.
class EmbreeDevice {
public:
    explicit EmbreeDevice(int threads, EmbreeIsa isa = EmbreeIsa::native);
    ~EmbreeDevice();
    EmbreeDevice(const EmbreeDevice&) = delete;
    EmbreeDevice& operator=(const EmbreeDevice&) = delete;

    RTCDevice handle() const { return device_; }
    std::int64_t live_bytes() const { return live_bytes_.load(); }
    /// Throws std::runtime_error naming what failed when Embree reported an error.
    void throw_on_error(const char* what) const;

private:
    static bool monitor_memory(void* self, ssize_t bytes, bool post);
    RTCDevice device_ = nullptr;
    std::atomic<std::int64_t> live_bytes_{0};
};

/// One committed scene. build_ms spans the same work as our structures' build: from the mesh in
/// memory to a structure ready to trace (copying into Embree's buffers included).
class EmbreeScene {
public:
    EmbreeScene(const EmbreeDevice& device, const Mesh& mesh, EmbreeQuality quality = EmbreeQuality::high);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    double build_ms() const { return build_ms_; }
    /// What the device's memory monitor saw this scene allocate (geometry buffers and the BVH).
    std::size_t bytes() const { return bytes_; }

    /// The camera's primary rays, closest hit: rtcIntersect1 per pixel for packet_width 1, else
    /// rtcIntersect4 / 8 / 16 over 2x2 / 4x2 / 4x4 pixel blocks, lanes past the image edge
    /// switched off in the valid mask. Blocks are spread over the calling thread pool.
    void trace(const Camera& camera, int packet_width, std::span<Hit> hits) const;
    /// The camera's primary rays, closest hit, as Embree's stream: rtcIntersect1M on each 8x8 block
    /// of pixels (coherent context), blocks spread over the calling thread pool in 16x16 tiles.
    void trace_stream(const Camera& camera, std::span<Hit> hits) const;
    /// Any-hit of each ray (shadow rays): rtcOccluded1 per ray for packet_width 1, else
    /// rtcOccluded4 / 8 / 16 on the packets our own traversals cut from the list
    /// (for_each_stream_packet, in chunks of kStreamChunkRays). Rays with tmax <= tmin are not
    /// traced (0). The context is coherent for rays in order, incoherent for rays by octant.
    void occluded(std::span<const Ray> rays, int packet_width, PacketGrouping grouping,
                  std::span<std::uint8_t> occluded) const;
    /// Closest hit of each ray (diffuse rays), with rtcIntersect1 or rtcIntersect4 / 8 / 16 the same way.
    void intersect(std::span<const Ray> rays, int packet_width, PacketGrouping grouping, std::span<Hit> hits) const;

private:
    void build(const EmbreeDevice& device, const Mesh& mesh, EmbreeQuality quality);  // fills and commits scene_
    RTCScene scene_ = nullptr;
    double build_ms_ = 0.0;
    std::size_t bytes_ = 0;
};

#endif  // TRIDENT_HAVE_EMBREE

}  // namespace trident::bench
