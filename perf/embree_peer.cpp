#include "perf/embree_peer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <vector>

#include "accel/util/timer.h"
#include "perf/embree_api.h"

namespace arbor::perf {

using accel::Hit;
using accel::Query;
using accel::Ray;
using embree_api::Context;

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();

/// Sums what the device allocates (negative sizes are frees).
bool monitor_memory(void* user, ssize_t bytes, bool) {
    static_cast<std::atomic<std::int64_t>*>(user)->fetch_add(bytes, std::memory_order_relaxed);
    return true;
}

[[noreturn]] void throw_embree(RTCDevice device, const char* what) {
    const RTCError e = rtcGetDeviceError(device);
    throw std::runtime_error(std::string("embree: ") + what + " failed (error " + std::to_string(int(e)) + ")");
}

/// Fills the RTCRay fields of one ray; untraceable rays become inactive (tnear > tfar) with a
/// harmless finite origin and direction, so that Embree never sees NaN or Inf.
template <class R>
void put_ray(R& r, const Ray& ray) {
    if (accel::ray_is_traceable(ray)) {
        r.org_x = ray.org.x, r.org_y = ray.org.y, r.org_z = ray.org.z, r.tnear = ray.tnear;
        r.dir_x = ray.dir.x, r.dir_y = ray.dir.y, r.dir_z = ray.dir.z, r.tfar = ray.tfar;
    } else {
        r.org_x = r.org_y = r.org_z = 0.0f, r.dir_x = 1.0f, r.dir_y = r.dir_z = 0.0f;
        r.tnear = 1.0f, r.tfar = 0.0f;
    }
    r.time = 0.0f;
    r.mask = 0xFFFFFFFFu;
    r.id = 0;
    r.flags = 0;
}

/// arbor's triangle number of Embree's (instance, prim): instance k's triangles follow the k
/// before it, `per` each (per = 0: no instances).
unsigned global_prim(unsigned inst, unsigned prim, unsigned per) {
    return inst == RTC_INVALID_GEOMETRY_ID ? prim : inst * per + prim;
}

Hit closest_hit(const RTCRayHit& rh, unsigned per) {
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return accel::miss_hit;
    return {rh.ray.tfar, global_prim(rh.hit.instID[0], rh.hit.primID, per), rh.hit.u, rh.hit.v};
}

/// Embree sets tfar = -inf on an occluded ray. The answer keeps t = tnear, prim = 0.
Hit any_hit(float tfar_after, float tnear) {
    if (tfar_after != -inf) return accel::miss_hit;
    return {tnear, 0u, 0.0f, 0.0f};
}

template <int N>
struct Packet;
template <>
struct Packet<8> {
    using RayHit = RTCRayHit8;
    using Ray = RTCRay8;
};
template <>
struct Packet<16> {
    using RayHit = RTCRayHit16;
    using Ray = RTCRay16;
};

/// Lane k of an SoA packet ray, written through the same put_ray as single rays.
template <class P>
struct LaneRef {
    P& p;
    int k;
};
template <class P>
void put_lane(P& p, int k, const Ray& ray) {
    struct One {
        float org_x, org_y, org_z, tnear, dir_x, dir_y, dir_z, time, tfar;
        unsigned mask, id, flags;
    } one;
    put_ray(one, ray);
    p.org_x[k] = one.org_x, p.org_y[k] = one.org_y, p.org_z[k] = one.org_z, p.tnear[k] = one.tnear;
    p.dir_x[k] = one.dir_x, p.dir_y[k] = one.dir_y, p.dir_z[k] = one.dir_z, p.tfar[k] = one.tfar;
    p.time[k] = 0.0f, p.mask[k] = 0xFFFFFFFFu, p.id[k] = 0, p.flags[k] = 0;
}

template <int N>
void trace_packets(RTCScene scene, Context& ctx, std::span<const Ray> rays, std::span<Hit> hits, Query q,
                   unsigned per) {
    using P = Packet<N>;
    for (std::size_t base = 0; base < rays.size(); base += N) {
        const int n = int(std::min<std::size_t>(N, rays.size() - base));
        alignas(64) int valid[N];
        if (q == Query::closest) {
            alignas(64) typename P::RayHit rh;
            for (int k = 0; k < N; ++k) {
                valid[k] = k < n && accel::ray_is_traceable(rays[base + std::size_t(k)]) ? -1 : 0;
                put_lane(rh.ray, k, k < n ? rays[base + std::size_t(k)] : Ray{});
                rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
            }
            embree_api::intersect(valid, scene, ctx, &rh);
            for (int k = 0; k < n; ++k)
                hits[base + std::size_t(k)] =
                    rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID || !valid[k]
                        ? accel::miss_hit
                        : Hit{rh.ray.tfar[k], global_prim(rh.hit.instID[0][k], rh.hit.primID[k], per), rh.hit.u[k],
                              rh.hit.v[k]};
        } else {
            alignas(64) typename P::Ray r;
            for (int k = 0; k < N; ++k) {
                valid[k] = k < n && accel::ray_is_traceable(rays[base + std::size_t(k)]) ? -1 : 0;
                put_lane(r, k, k < n ? rays[base + std::size_t(k)] : Ray{});
            }
            embree_api::occluded(valid, scene, ctx, &r);
            for (int k = 0; k < n; ++k)
                hits[base + std::size_t(k)] = valid[k] ? any_hit(r.tfar[k], r.tnear[k]) : accel::miss_hit;
        }
    }
}

}  // namespace

struct EmbreePeer::Impl {
    EmbreeConfig cfg;
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    RTCScene object = nullptr;    ///< the instanced mesh's own scene (two-level scenes only)
    unsigned per_instance = 0;    ///< its triangle count (two-level scenes only)
    std::vector<float> vertices;  // x, y, z, pad per vertex (+ 4 floats: Embree reads 16 bytes)
    std::atomic<std::int64_t> bytes{0};
    double build_ms = 0.0, setup_ms = 0.0;
    std::size_t memory_bytes = 0, triangles = 0;

    /// The device, with its memory monitor, and the (top) scene, empty.
    void start(const EmbreeConfig& config);
    /// A triangle geometry over a copy of `tris`' vertices, attached to `target` as geometry 0.
    void attach_triangles(RTCScene target, const accel::TriangleView& tris);
    /// Commits `target`, adding its time to build_ms and what it allocated to memory_bytes.
    void commit(RTCScene target);

    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (object) rtcReleaseScene(object);
        if (device) rtcReleaseDevice(device);
    }
};

std::string_view to_string(EmbreeCall c) {
    switch (c) {
        case EmbreeCall::single:
            return "1";
        case EmbreeCall::packet8:
            return "8";
        case EmbreeCall::packet16:
            return "16";
        case EmbreeCall::stream:
            return "1M";
    }
    return "?";
}

namespace {
#if ARBOR_EMBREE_STREAM
constexpr EmbreeCall calls[] = {EmbreeCall::single, EmbreeCall::packet8, EmbreeCall::packet16, EmbreeCall::stream};
#else
constexpr EmbreeCall calls[] = {EmbreeCall::single, EmbreeCall::packet8, EmbreeCall::packet16};
#endif
}  // namespace

std::span<const EmbreeCall> embree_calls() { return calls; }

bool embree_has(EmbreeCall c) { return std::find(std::begin(calls), std::end(calls), c) != std::end(calls); }

std::string embree_config_name(const EmbreeConfig& cfg) {
    std::string s = "embree";
    if (cfg.high_quality) s += "-high";
    if (cfg.robust) s += "-robust";
    if (cfg.copy_indices) s += "-copy";
    return s;
}

namespace {
/// Embree's device configuration: ARBOR_EMBREE_DEVICE when set (e.g. "isa=sse4.2", to measure the
/// peer as an SSE-only machine would run it), else Embree's defaults.
const char* device_config() { return std::getenv("ARBOR_EMBREE_DEVICE"); }

/// An empty scene with cfg's flags and quality.
RTCScene new_scene(RTCDevice device, const EmbreeConfig& cfg) {
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, cfg.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
    rtcSetSceneBuildQuality(scene, cfg.high_quality ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
    return scene;
}
}  // namespace

void EmbreePeer::Impl::start(const EmbreeConfig& config) {
    Impl& m = *this;
    m.cfg = config;
    m.device = rtcNewDevice(device_config());
    if (!m.device)
        throw std::runtime_error(device_config()
                                     ? std::string("embree: rtcNewDevice failed with ARBOR_EMBREE_DEVICE=\"") +
                                           device_config() + "\""
                                     : std::string("embree: rtcNewDevice failed"));
    rtcSetDeviceMemoryMonitorFunction(m.device, monitor_memory, &m.bytes);
    m.scene = new_scene(m.device, config);
}

void EmbreePeer::Impl::attach_triangles(RTCScene target, const accel::TriangleView& tris) {
    Impl& m = *this;
    m.triangles = tris.triangle_count();
    RTCGeometry geom = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    const std::size_t nv = tris.vertex_count();
    m.vertices.assign(4 * nv + 4, 0.0f);
    for (std::size_t i = 0; i < nv; ++i) {
        m.vertices[4 * i] = tris.x[i];
        m.vertices[4 * i + 1] = tris.y[i];
        m.vertices[4 * i + 2] = tris.z[i];
    }
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, m.vertices.data(), 0,
                               4 * sizeof(float), nv);
    if (cfg.copy_indices) {
        auto* idx = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), m.triangles));
        if (!idx) throw_embree(m.device, "rtcSetNewGeometryBuffer");
        std::copy(tris.indices.begin(), tris.indices.end(), idx);
    } else {
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, tris.indices.data(), 0,
                                   3 * sizeof(std::uint32_t), m.triangles);
    }
    rtcSetGeometryBuildQuality(geom, cfg.high_quality ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(target, geom);  // geometry 0: every geomID is 0
    rtcReleaseGeometry(geom);
    if (rtcGetDeviceError(m.device) != RTC_ERROR_NONE) throw_embree(m.device, "scene setup");
}

void EmbreePeer::Impl::commit(RTCScene target) {
    Impl& m = *this;
    const std::int64_t before = m.bytes.load();
    const accel::Timer build;
    rtcCommitScene(target);
    m.build_ms += build.ms();
    if (rtcGetDeviceError(m.device) != RTC_ERROR_NONE) throw_embree(m.device, "rtcCommitScene");
    m.memory_bytes += std::size_t(std::max<std::int64_t>(0, m.bytes.load() - before));
}

EmbreePeer::EmbreePeer(const accel::TriangleView& tris, const EmbreeConfig& cfg) : impl_(std::make_unique<Impl>()) {
    const accel::Timer setup;
    impl_->start(cfg);
    impl_->attach_triangles(impl_->scene, tris);
    impl_->setup_ms = setup.ms();
    impl_->commit(impl_->scene);
}

EmbreePeer::EmbreePeer(const accel::TriangleView& mesh, std::span<const accel::Affine> placements,
                       const EmbreeConfig& cfg)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    accel::Timer setup;
    m.start(cfg);
    m.object = new_scene(m.device, cfg);
    m.attach_triangles(m.object, mesh);
    m.per_instance = unsigned(m.triangles);
    m.setup_ms = setup.ms();
    // The instanced scene is committed before the instances that name it.
    m.commit(m.object);
    setup = accel::Timer{};
    for (const accel::Affine& a : placements) {
        RTCGeometry inst = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(inst, m.object);
        float xf[12];
        for (std::size_t i = 0; i < 12; ++i) xf[i] = float(a.m[i]);
        rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xf);
        rtcCommitGeometry(inst);
        rtcAttachGeometry(m.scene, inst);  // instance k is geometry k: instID[0] = k
        rtcReleaseGeometry(inst);
    }
    if (rtcGetDeviceError(m.device) != RTC_ERROR_NONE) throw_embree(m.device, "instance setup");
    m.setup_ms += setup.ms();
    m.commit(m.scene);
}

EmbreePeer::~EmbreePeer() = default;

const EmbreeConfig& EmbreePeer::config() const { return impl_->cfg; }
double EmbreePeer::build_ms() const { return impl_->build_ms; }
double EmbreePeer::setup_ms() const { return impl_->setup_ms; }
std::size_t EmbreePeer::memory_bytes() const { return impl_->memory_bytes; }
std::size_t EmbreePeer::triangles() const { return impl_->triangles; }

void EmbreePeer::trace(std::span<const Ray> rays, std::span<Hit> hits, Query query, EmbreeCall call,
                       bool coherent) const {
    if (!embree_has(call))
        throw std::invalid_argument("embree: Embree " + std::to_string(RTC_VERSION_MAJOR) + " has no call " +
                                    std::string(to_string(call)));
    Context ctx(coherent);
    RTCScene scene = impl_->scene;
    const unsigned per = impl_->per_instance;
    const std::size_t n = std::min(rays.size(), hits.size());
    rays = rays.first(n);
    hits = hits.first(n);

    switch (call) {
        case EmbreeCall::packet8:
            trace_packets<8>(scene, ctx, rays, hits, query, per);
            return;
        case EmbreeCall::packet16:
            trace_packets<16>(scene, ctx, rays, hits, query, per);
            return;
        case EmbreeCall::single:
            for (std::size_t i = 0; i < n; ++i) {
                if (query == Query::closest) {
                    RTCRayHit rh;
                    put_ray(rh.ray, rays[i]);
                    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                    embree_api::intersect(scene, ctx, &rh);
                    hits[i] = closest_hit(rh, per);
                } else {
                    RTCRay r;
                    put_ray(r, rays[i]);
                    embree_api::occluded(scene, ctx, &r);
                    hits[i] = accel::ray_is_traceable(rays[i]) ? any_hit(r.tfar, r.tnear) : accel::miss_hit;
                }
            }
            return;
        case EmbreeCall::stream: {
#if ARBOR_EMBREE_STREAM
            // Sub-batches on the stack: no allocation while timing; Embree's stream code works on
            // small blocks internally anyway.
            constexpr std::size_t block = 256;
            for (std::size_t base = 0; base < n; base += block) {
                const std::size_t m = std::min(block, n - base);
                if (query == Query::closest) {
                    RTCRayHit rh[block];
                    for (std::size_t k = 0; k < m; ++k) {
                        put_ray(rh[k].ray, rays[base + k]);
                        rh[k].hit.geomID = RTC_INVALID_GEOMETRY_ID;
                        rh[k].hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                    }
                    embree_api::intersect_stream(scene, ctx, rh, unsigned(m));
                    for (std::size_t k = 0; k < m; ++k) hits[base + k] = closest_hit(rh[k], per);
                } else {
                    RTCRay r[block];
                    for (std::size_t k = 0; k < m; ++k) put_ray(r[k], rays[base + k]);
                    embree_api::occluded_stream(scene, ctx, r, unsigned(m));
                    for (std::size_t k = 0; k < m; ++k)
                        hits[base + k] =
                            accel::ray_is_traceable(rays[base + k]) ? any_hit(r[k].tfar, r[k].tnear) : accel::miss_hit;
                }
            }
#endif
            return;
        }
    }
}

void EmbreePeer::trace_parallel(std::span<const Ray> rays, std::span<Hit> hits, Query query, EmbreeCall call,
                                bool coherent, std::size_t chunk) const {
    const std::size_t n = std::min(rays.size(), hits.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, std::max<std::size_t>(chunk, 1)),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          trace(rays.subspan(r.begin(), r.size()), hits.subspan(r.begin(), r.size()), query, call,
                                coherent);
                      });
}

std::string embree_description() {
    RTCDevice d = rtcNewDevice(device_config());
    if (!d) return "Embree (device creation failed)";
    auto prop = [&](RTCDeviceProperty p) { return rtcGetDeviceProperty(d, p); };
    std::string s = "Embree " + std::to_string(prop(RTC_DEVICE_PROPERTY_VERSION_MAJOR)) + "." +
                    std::to_string(prop(RTC_DEVICE_PROPERTY_VERSION_MINOR)) + "." +
                    std::to_string(prop(RTC_DEVICE_PROPERTY_VERSION_PATCH));
    s += std::string(" (native packets:") + (prop(RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED) ? " 4" : "") +
         (prop(RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) ? " 8" : "") +
         (prop(RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) ? " 16" : "") +
#if ARBOR_EMBREE_STREAM
         "; stream: " + (prop(RTC_DEVICE_PROPERTY_RAY_STREAM_SUPPORTED) ? "yes" : "no") +
#else
         "; stream: none in Embree " + std::to_string(RTC_VERSION_MAJOR) +
#endif
         "; tasking: " + (prop(RTC_DEVICE_PROPERTY_TASKING_SYSTEM) == 1 ? "TBB" : "internal") + ")";
    if (device_config()) s += std::string(" [ARBOR_EMBREE_DEVICE: ") + device_config() + "]";
    rtcReleaseDevice(d);
    return s;
}

}  // namespace arbor::perf
