// Google Benchmark microbenchmarks of the simd/ kernels: ray/box and ray/triangle, scalar against
// 4/8/16-wide, packets of 4/8/16 rays, and the helpers around them. Every benchmark loops over
// arrays of different rays and boxes/triangles that sit in L1, so the numbers are the kernels'
// throughput (independent tests back to back), not the latency a traversal step would see.
// The counters are the CPU time per single ray-box or ray-triangle test ("per_test") and per kernel
// call ("per_call": one call tests lanes<T> boxes/triangles, or a packet of lanes<T> rays).
// How to run: perf/README.md.
#include "perf/commands.h"
#include "accel/core/ray.h"
#include "simd/box_kernels.h"
#include "simd/lane_order.h"
#include "simd/packet_bounds.h"
#include "simd/tri_kernels.h"

#include <benchmark/benchmark.h>

#include <array>
#include <random>
#include <span>
#include <vector>

namespace {

using arbor::accel::Ray;
using namespace arbor::simd;

constexpr std::size_t ray_count = 256;  // distinct rays per benchmark iteration
constexpr std::size_t geom_count = 64;  // distinct nodes / triangle blocks / boxes

float uniform(std::mt19937& rng, float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }
Vec3f uniform3(std::mt19937& rng, float lo, float hi) {
    return {uniform(rng, lo, hi), uniform(rng, lo, hi), uniform(rng, lo, hi)};
}

/// Incoherent rays from a shell around [-1, 1]^3 towards points inside it.
std::vector<Ray> random_rays(std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<Ray> rays(ray_count);
    for (Ray& r : rays) {
        r.org = uniform3(rng, -3.0f, 3.0f);
        r.dir = uniform3(rng, -1.0f, 1.0f) - r.org;
        r.tnear = 0.0f;
        r.tfar = INFINITY;
    }
    return rays;
}
/// Coherent rays: a pinhole grid looking down -z at [-1, 1]^2 (one Woop permutation for all).
std::vector<Ray> coherent_rays() {
    std::vector<Ray> rays(ray_count);
    for (std::size_t i = 0; i < ray_count; ++i) {
        const float x = float(i % 16) / 8.0f - 1.0f, y = float(i / 16) / 8.0f - 1.0f;
        rays[i] = {{0.0f, 0.0f, 3.0f}, 0.0f, {x * 0.33f, y * 0.33f, -1.0f}, INFINITY};
    }
    return rays;
}
/// Boxes of size 0.1..0.6 inside [-1, 1]^3 (a fair share of hits for the random rays).
std::vector<std::pair<Vec3f, Vec3f>> random_boxes(std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<std::pair<Vec3f, Vec3f>> b(n);
    for (auto& [lo, hi] : b) {
        lo = uniform3(rng, -1.0f, 0.5f);
        hi = lo + uniform3(rng, 0.1f, 0.6f);
    }
    return b;
}
/// Triangles of edge ~0.2..0.6 inside [-1, 1]^3.
std::vector<std::array<Vec3f, 3>> random_triangles(std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<std::array<Vec3f, 3>> t(n);
    for (auto& tri : t) {
        const Vec3f c = uniform3(rng, -1.0f, 1.0f);
        tri = {c + uniform3(rng, -0.3f, 0.3f), c + uniform3(rng, -0.3f, 0.3f), c + uniform3(rng, -0.3f, 0.3f)};
    }
    return t;
}

void set_counters(benchmark::State& state, std::size_t tests_per_iteration, std::size_t calls_per_iteration) {
    using benchmark::Counter;
    // Inverted rates: seconds (CPU time) per test and per kernel call, printed with an SI prefix (e.g. 0.2ns).
    state.counters["per_test"] = Counter(double(tests_per_iteration), Counter::kIsIterationInvariantRate | Counter::kInvert);
    state.counters["per_call"] = Counter(double(calls_per_iteration), Counter::kIsIterationInvariantRate | Counter::kInvert);
    state.SetItemsProcessed(std::int64_t(state.iterations() * tests_per_iteration));
}

// ---- one ray against boxes ------------------------------------------------------------------

/// The scalar oracle form, slab_test(SlabRay, lo, hi): what the scalar BVH traversal calls.
void BM_box_scalar_oracle(benchmark::State& state) {
    const auto rays = random_rays(1);
    const auto boxes = random_boxes(geom_count, 2);
    std::vector<SlabRay> slabs;
    for (const Ray& r : rays) slabs.push_back(slab_ray(r.org, r.dir));
    for (auto _ : state) {
        std::uint32_t hits = 0;
        for (const SlabRay& s : slabs)
            for (const auto& [lo, hi] : boxes) {
                float t;
                hits += slab_test(s, lo, hi, 0.0f, INFINITY, t);
            }
        benchmark::DoNotOptimize(hits);
    }
    set_counters(state, ray_count * geom_count, ray_count * geom_count);
}
BENCHMARK(BM_box_scalar_oracle);

/// The per-ray setup of the single-ray SIMD path: wide_ray (reciprocals, Woop shear, broadcasts).
template <class T> void BM_wide_ray(benchmark::State& state) {
    const auto rays = random_rays(3);
    for (auto _ : state) {
        float sum = 0.0f;
        for (const Ray& r : rays) {
            const WideRay<T> w = wide_ray<T>(r.org, r.dir, r.tnear, r.tfar);
            benchmark::DoNotOptimize(&w);
            sum += lane(w.sz, 0);
        }
        benchmark::DoNotOptimize(sum);
    }
    set_counters(state, ray_count, ray_count);
}
BENCHMARK_TEMPLATE(BM_wide_ray, Float4);
#if XSIMD_WITH_AVX512F
BENCHMARK_TEMPLATE(BM_wide_ray, Float16);
#endif

/// One ray against a wide node of lanes<T> boxes (T = float: the scalar instantiation, 1 box).
template <class T> void BM_ray_boxes(benchmark::State& state) {
    constexpr std::size_t n = lanes<T>;
    const auto rays = random_rays(1);
    const auto boxes = random_boxes(geom_count * n, 2);
    std::vector<BoxesSoA<n>> nodes(geom_count);
    for (std::size_t j = 0; j < boxes.size(); ++j) nodes[j / n].set(j % n, boxes[j].first, boxes[j].second);
    std::vector<WideRay<T>> wide;
    for (const Ray& r : rays) wide.push_back(wide_ray<T>(r.org, r.dir, r.tnear, r.tfar));
    for (auto _ : state) {
        std::uint32_t hits = 0;
        for (const WideRay<T>& w : wide)
            for (const BoxesSoA<n>& node : nodes) {
                T t;
                hits += to_bits(ray_boxes(w, node, t));
            }
        benchmark::DoNotOptimize(hits);
    }
    set_counters(state, ray_count * geom_count * n, ray_count * geom_count);
}
BENCHMARK_TEMPLATE(BM_ray_boxes, float);
BENCHMARK_TEMPLATE(BM_ray_boxes, Float4);
#if XSIMD_WITH_AVX2
BENCHMARK_TEMPLATE(BM_ray_boxes, Float8);
#endif
#if XSIMD_WITH_AVX512F
BENCHMARK_TEMPLATE(BM_ray_boxes, Float16);
#endif

/// The same plus ordering the hit children nearest first (what a wide traversal step does).
template <class T> void BM_ray_boxes_ordered(benchmark::State& state) {
    constexpr std::size_t n = lanes<T>;
    const auto rays = random_rays(1);
    const auto boxes = random_boxes(geom_count * n, 2);
    std::vector<BoxesSoA<n>> nodes(geom_count);
    for (std::size_t j = 0; j < boxes.size(); ++j) nodes[j / n].set(j % n, boxes[j].first, boxes[j].second);
    std::vector<WideRay<T>> wide;
    for (const Ray& r : rays) wide.push_back(wide_ray<T>(r.org, r.dir, r.tnear, r.tfar));
    for (auto _ : state) {
        std::uint32_t acc = 0;
        for (const WideRay<T>& w : wide)
            for (const BoxesSoA<n>& node : nodes) {
                T t;
                std::uint8_t order[32];
                const int count = order_hits(to_bits(ray_boxes(w, node, t)), t, order);
                acc += count ? order[0] + std::uint32_t(count) : 0u;
            }
        benchmark::DoNotOptimize(acc);
    }
    set_counters(state, ray_count * geom_count * n, ray_count * geom_count);
}
BENCHMARK_TEMPLATE(BM_ray_boxes_ordered, Float4);
#if XSIMD_WITH_AVX2
BENCHMARK_TEMPLATE(BM_ray_boxes_ordered, Float8);
#endif
#if XSIMD_WITH_AVX512F
BENCHMARK_TEMPLATE(BM_ray_boxes_ordered, Float16);
#endif

// ---- one ray against triangles --------------------------------------------------------------

/// The scalar oracle form, woop_test: what brute and the scalar traversal call.
void BM_tri_scalar_oracle(benchmark::State& state) {
    const auto rays = random_rays(3);
    const auto tris = random_triangles(geom_count, 4);
    std::vector<WoopShear> shears;
    for (const Ray& r : rays) shears.push_back(woop_shear(r.dir));
    for (auto _ : state) {
        std::uint32_t hits = 0;
        for (std::size_t i = 0; i < rays.size(); ++i)
            for (const auto& t : tris) hits += woop_test(rays[i].org, shears[i], 0.0f, INFINITY, t[0], t[1], t[2]).hit;
        benchmark::DoNotOptimize(hits);
    }
    set_counters(state, ray_count * geom_count, ray_count * geom_count);
}
BENCHMARK(BM_tri_scalar_oracle);

/// One ray against a block of lanes<T> triangles; Closest = also pick the nearest hit lane.
template <class T, bool Closest> void BM_ray_triangles(benchmark::State& state) {
    constexpr std::size_t n = lanes<T>;
    const auto rays = random_rays(3);
    const auto tris = random_triangles(geom_count * n, 4);
    std::vector<TrisSoA<n>> blocks(geom_count);
    for (std::size_t j = 0; j < tris.size(); ++j) blocks[j / n].set(j % n, tris[j][0], tris[j][1], tris[j][2]);
    std::vector<WideRay<T>> wide;
    for (const Ray& r : rays) wide.push_back(wide_ray<T>(r.org, r.dir, r.tnear, r.tfar));
    for (auto _ : state) {
        std::uint32_t acc = 0;
        for (const WideRay<T>& w : wide)
            for (const TrisSoA<n>& b : blocks) {
                const TriHit<T> h = ray_triangles(w, b);
                if constexpr (Closest) acc += std::uint32_t(closest_lane(h.hit, h.t) + 1);
                else acc += to_bits(h.hit);
            }
        benchmark::DoNotOptimize(acc);
    }
    set_counters(state, ray_count * geom_count * n, ray_count * geom_count);
}
BENCHMARK_TEMPLATE(BM_ray_triangles, float, false);
BENCHMARK_TEMPLATE(BM_ray_triangles, Float4, false);
BENCHMARK_TEMPLATE(BM_ray_triangles, Float4, true);
#if XSIMD_WITH_AVX2
BENCHMARK_TEMPLATE(BM_ray_triangles, Float8, false);
BENCHMARK_TEMPLATE(BM_ray_triangles, Float8, true);
#endif
#if XSIMD_WITH_AVX512F
BENCHMARK_TEMPLATE(BM_ray_triangles, Float16, false);
BENCHMARK_TEMPLATE(BM_ray_triangles, Float16, true);
#endif

// ---- packets --------------------------------------------------------------------------------

template <class T> std::vector<RayPacket<T>> packets_of(const std::vector<Ray>& rays) {
    std::vector<RayPacket<T>> p;
    for (std::size_t s = 0; s < rays.size(); s += lanes<T>)
        p.push_back(load_packet<T, Ray>(std::span<const Ray>(rays).subspan(s, lanes<T>)));
    return p;
}

/// A packet of lanes<T> rays against one box (a packet traversal step); ns/test is per ray.
template <class T> void BM_packet_box(benchmark::State& state) {
    const auto packets = packets_of<T>(coherent_rays());
    const auto boxes = random_boxes(geom_count, 5);
    for (auto _ : state) {
        std::uint32_t hits = 0;
        for (const RayPacket<T>& p : packets)
            for (const auto& [lo, hi] : boxes) {
                T t;
                hits += to_bits(packet_box(p, lo, hi, t));
            }
        benchmark::DoNotOptimize(hits);
    }
    set_counters(state, ray_count * geom_count, packets.size() * geom_count);
}
BENCHMARK_TEMPLATE(BM_packet_box, float);
BENCHMARK_TEMPLATE(BM_packet_box, Float4);
#if XSIMD_WITH_AVX2
BENCHMARK_TEMPLATE(BM_packet_box, Float8);
#endif
#if XSIMD_WITH_AVX512F
BENCHMARK_TEMPLATE(BM_packet_box, Float16);
#endif

/// The interval bounds of a packet (once per packet, before its walk): Batched = packet_bounds
/// (16 lanes: the reductions batched), else packet_bounds_plain; ns/call is per packet.
template <class T, bool Batched> void BM_packet_bounds(benchmark::State& state) {
    const auto packets = packets_of<T>(coherent_rays());
    for (auto _ : state) {
        for (const RayPacket<T>& p : packets) {
            PacketBounds b = Batched ? packet_bounds(p, p.active) : packet_bounds_plain(p, p.active);
            benchmark::DoNotOptimize(b);  // every field, or the unread reductions would be dropped
        }
    }
    set_counters(state, ray_count, packets.size());
}
#if XSIMD_WITH_AVX2
BENCHMARK_TEMPLATE(BM_packet_bounds, Float8, false);
#endif
#if XSIMD_WITH_AVX512F
BENCHMARK_TEMPLATE(BM_packet_bounds, Float16, false);
BENCHMARK_TEMPLATE(BM_packet_bounds, Float16, true);
#endif

/// A packet against one triangle. Coherent: all lanes share a permutation. Mode 0: packet_triangle
/// (uniform fast path when possible), 1: packet_triangle_lanes (per-lane selects always).
template <class T, bool Coherent, int Mode> void BM_packet_triangle(benchmark::State& state) {
    const auto packets = packets_of<T>(Coherent ? coherent_rays() : random_rays(6));
    const auto tris = random_triangles(geom_count, 7);
    for (auto _ : state) {
        std::uint32_t hits = 0;
        for (const RayPacket<T>& p : packets)
            for (const auto& t : tris) {
                const TriHit<T> h = Mode == 0 ? packet_triangle(p, t[0], t[1], t[2])
                                              : packet_triangle_lanes(p, t[0], t[1], t[2]);
                hits += to_bits(h.hit);
            }
        benchmark::DoNotOptimize(hits);
    }
    set_counters(state, ray_count * geom_count, packets.size() * geom_count);
}
BENCHMARK_TEMPLATE(BM_packet_triangle, float, true, 0);
BENCHMARK_TEMPLATE(BM_packet_triangle, Float4, true, 0);
BENCHMARK_TEMPLATE(BM_packet_triangle, Float4, true, 1);
#if XSIMD_WITH_AVX2
BENCHMARK_TEMPLATE(BM_packet_triangle, Float8, true, 0);
BENCHMARK_TEMPLATE(BM_packet_triangle, Float8, true, 1);
BENCHMARK_TEMPLATE(BM_packet_triangle, Float8, false, 0);
BENCHMARK_TEMPLATE(BM_packet_triangle, Float8, false, 1);
#endif
#if XSIMD_WITH_AVX512F
BENCHMARK_TEMPLATE(BM_packet_triangle, Float16, true, 0);
BENCHMARK_TEMPLATE(BM_packet_triangle, Float16, true, 1);
BENCHMARK_TEMPLATE(BM_packet_triangle, Float16, false, 0);
BENCHMARK_TEMPLATE(BM_packet_triangle, Float16, false, 1);
#endif

/// Setting rays up: load_packet (transpose + per-lane constants) and wide_ray (broadcast); ns/test
/// is per ray.
template <class T> void BM_load_packet(benchmark::State& state) {
    const auto rays = random_rays(8);
    for (auto _ : state) {
        for (std::size_t s = 0; s < rays.size(); s += lanes<T>) {
            RayPacket<T> p = load_packet<T, Ray>(std::span<const Ray>(rays).subspan(s, lanes<T>));
            benchmark::DoNotOptimize(p);
        }
    }
    set_counters(state, ray_count, ray_count / lanes<T>);
}
BENCHMARK_TEMPLATE(BM_load_packet, float);
#if XSIMD_WITH_AVX2
BENCHMARK_TEMPLATE(BM_load_packet, Float8);
#endif
#if XSIMD_WITH_AVX512F
BENCHMARK_TEMPLATE(BM_load_packet, Float16);
#endif

template <class T, bool Coherent> void BM_wide_ray(benchmark::State& state) {
    const auto rays = Coherent ? coherent_rays() : random_rays(9);
    for (auto _ : state)
        for (const Ray& r : rays) {
            WideRay<T> w = wide_ray<T>(r.org, r.dir, r.tnear, r.tfar);
            benchmark::DoNotOptimize(w);
        }
    set_counters(state, ray_count, ray_count);
}
#if XSIMD_WITH_AVX2
BENCHMARK_TEMPLATE(BM_wide_ray, Float8, false);
BENCHMARK_TEMPLATE(BM_wide_ray, Float8, true);
#endif

}  // namespace

int arbor::perf::kernels_command(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
