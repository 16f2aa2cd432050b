// The machine side of the limit model (perf/limit_kernels.h): the wide walk's two kernels timed
// with hot caches, and the streaming read bandwidth.
#include "perf/limit_kernels.h"

#include "simd/box_kernels.h"
#include "simd/ray_box.h"
#include "simd/ray_triangle.h"
#include "simd/tri_kernels.h"

#include <x86intrin.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace arbor::perf {

namespace {

using namespace arbor::simd;
using Clock = std::chrono::steady_clock;

constexpr std::size_t ray_count = 256;  // distinct rays
constexpr std::size_t geom_count = 32;  // distinct nodes / blocks: 16 KiB of 16-wide nodes, 18 KiB of blocks (L1)
constexpr int timing_runs = 101;        // short timings, many: on a loaded machine some run is not preempted

/// Keeps `v` alive: the compiler must compute it, and cannot move the work out of the loop.
template <class X>
inline void keep(const X& v) {
    asm volatile("" : : "m"(v) : "memory");
}

float uniform(std::mt19937& rng, float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }
Vec3f uniform3(std::mt19937& rng, float lo, float hi) {
    return {uniform(rng, lo, hi), uniform(rng, lo, hi), uniform(rng, lo, hi)};
}

struct TestRay {
    Vec3f org, dir;
};
/// Incoherent rays from a shell around [-1, 1]^3 towards points inside it (tnear 0, tfar inf).
std::vector<TestRay> test_rays() {
    std::mt19937 rng(11);
    std::vector<TestRay> rays(ray_count);
    for (TestRay& r : rays) {
        r.org = uniform3(rng, -3.0f, 3.0f);
        r.dir = uniform3(rng, -0.5f, 0.5f) - r.org;
    }
    return rays;
}

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// The best (least) and the median of `runs` timings, after one untimed run, of `work` (seconds each).
template <class Work>
std::pair<double, double> best_and_median(Work&& work, int runs = timing_runs) {
    work();  // warm-up: caches, and the clock's ramp
    std::vector<double> s;
    for (int i = 0; i < runs; ++i) {
        const auto t0 = Clock::now();
        work();
        s.push_back(seconds_since(t0));
    }
    std::sort(s.begin(), s.end());
    return {s.front(), s[s.size() / 2]};
}

/// Kernel times of width N: the node test (ray_boxes_plain, as the walk's plain rays take it) and
/// the block test (ray_triangles with the walk's early out), each checked lane by lane against the
/// scalar oracles (slab_test, woop_test) on the benchmark's inputs first.
template <class T>
KernelTimes time_kernels(double tsc_ghz) {
    constexpr std::size_t n = lanes<T>;
    const std::vector<TestRay> rays = test_rays();
    std::mt19937 rng(5);
    std::vector<BoxesSoA<n>> nodes(geom_count);
    std::vector<TrisSoA<n>> blocks(geom_count);
    for (std::size_t g = 0; g < geom_count; ++g)
        for (std::size_t l = 0; l < n; ++l) {
            const Vec3f lo = uniform3(rng, -1.0f, 0.6f);
            nodes[g].set(l, lo, lo + uniform3(rng, 0.1f, 0.5f));
            const Vec3f c = uniform3(rng, -0.8f, 0.8f);
            blocks[g].set(l, c + uniform3(rng, -0.3f, 0.3f), c + uniform3(rng, -0.3f, 0.3f),
                          c + uniform3(rng, -0.3f, 0.3f));
        }
    std::vector<WideRay<T>> wide;
    for (const TestRay& r : rays) wide.push_back(wide_ray<T>(r.org, r.dir, 0.0f, INFINITY));

    // The oracles: every lane of every test the timing repeats.
    KernelTimes k;
    k.width = n;
    std::uint64_t box_hits = 0, tri_hits = 0, block_any = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!wide[i].plain) throw std::runtime_error("limit kernels: a benchmark ray is not plain");
        const SlabRay s = slab_ray(rays[i].org, rays[i].dir);
        const WoopShear w = woop_shear(rays[i].dir);
        for (std::size_t g = 0; g < geom_count; ++g) {
            T t;
            const std::uint32_t bits = to_bits(ray_boxes_plain<T>(wide[i], &nodes[g].b[0][0][0], t));
            const TriHit<T> h = ray_triangles<T, true>(wide[i], &blocks[g].v[0][0][0]);
            const std::uint32_t tri_bits = to_bits(h.hit);
            block_any += tri_bits != 0;
            for (std::size_t l = 0; l < n; ++l) {
                float te;
                const bool box = slab_test(s, nodes[g].lo(l), nodes[g].hi(l), 0.0f, INFINITY, te);
                if (box != bool(bits >> l & 1u) || (box && te != lane(t, l)))
                    throw std::runtime_error("limit kernels: ray_boxes_plain differs from slab_test (width " +
                                             std::to_string(n) + ")");
                box_hits += box;
                const Vec3f v0{blocks[g].v[0][0][l], blocks[g].v[0][1][l], blocks[g].v[0][2][l]};
                const Vec3f v1{blocks[g].v[1][0][l], blocks[g].v[1][1][l], blocks[g].v[1][2][l]};
                const Vec3f v2{blocks[g].v[2][0][l], blocks[g].v[2][1][l], blocks[g].v[2][2][l]};
                const TriHit<float> o = woop_test(rays[i].org, w, 0.0f, INFINITY, v0, v1, v2);
                const bool hit = tri_bits >> l & 1u;
                if (bool(o.hit) != hit || (hit && (o.t != lane(h.t, l) || o.u != lane(h.u, l) || o.v != lane(h.v, l))))
                    throw std::runtime_error("limit kernels: ray_triangles differs from woop_test (width " +
                                             std::to_string(n) + ")");
                tri_hits += hit;
            }
        }
    }
    const double tests = double(ray_count * geom_count);
    k.checked_tests = std::uint64_t(tests) * n * 2;
    k.box_hit_fraction = double(box_hits) / (tests * n);
    k.block_hit_fraction = double(block_any) / tests;
    (void)tri_hits;

    const int loops = 8;  // 65536 tests per timing (0.1-2 ms)
    // Throughput: independent tests back to back (the out-of-order core overlaps them).
    const auto [node_best, node_median] = best_and_median([&] {
        std::uint32_t acc = 0;
        for (int rep = 0; rep < loops; ++rep)
            for (const WideRay<T>& w : wide)
                for (const BoxesSoA<n>& node : nodes) {
                    T t;  // (the mask is computed from the entry and exit distances: t is computed too)
                    acc += to_bits(ray_boxes_plain<T>(w, &node.b[0][0][0], t));
                }
        keep(acc);
    });
    const auto [tri_best, tri_median] = best_and_median([&] {
        std::uint32_t acc = 0;
        T sum(0.0f);  // t, u and v used, so that the division is kept (one add chain: far below a test's time)
        for (int rep = 0; rep < loops; ++rep)
            for (const WideRay<T>& w : wide)
                for (const TrisSoA<n>& b : blocks) {
                    const TriHit<T> h = ray_triangles<T, true>(w, &b.v[0][0][0]);
                    acc += to_bits(h.hit);
                    sum += select(h.hit, h.t + h.u + h.v, T(0.0f));
                }
        keep(acc);
        keep(sum);
    });
    // Latency: each test's node chosen by the previous test's outcome, as in a walk (one ray's
    // steps depend on each other).
    const auto [chain_best, chain_median] = best_and_median([&] {
        std::uint32_t idx = 0;
        for (int rep = 0; rep < loops; ++rep)
            for (const WideRay<T>& w : wide)
                for (std::size_t g = 0; g < geom_count; ++g) {
                    T t;
                    const std::uint32_t bits = to_bits(ray_boxes_plain<T>(w, &nodes[idx].b[0][0][0], t));
                    idx = (idx + 1 + (bits & 1u)) % geom_count;
                }
        keep(idx);
    });
    const double per = 1e9 / (tests * loops);
    k.node_ns = node_best * per, k.node_ns_median = node_median * per;
    k.block_ns = tri_best * per, k.block_ns_median = tri_median * per;
    k.node_chain_ns = chain_best * per, k.node_chain_ns_median = chain_median * per;
    k.node_cycles = k.node_ns * tsc_ghz;
    k.block_cycles = k.block_ns * tsc_ghz;
    k.node_chain_cycles = k.node_chain_ns * tsc_ghz;
    return k;
}

/// GB/s of a streaming read of `floats` floats by `threads` threads (each a contiguous part, read
/// `passes` times: enough that a timing of a buffer in the caches is not the threads' start), best
/// of `runs`.
double read_bandwidth(const float* data, std::size_t floats, unsigned threads, int runs, int passes) {
    const auto part = [&](std::size_t lo, std::size_t hi, float* out) {
        using F = FloatV;
        constexpr std::size_t w = lanes<F>;
        float sum = 0.0f;
        for (int p = 0; p < passes; ++p) {
            F a(0.0f), b(0.0f), c(0.0f), d(0.0f);
            for (std::size_t i = lo; i + 4 * w <= hi; i += 4 * w) {
                a += load_lanes<F>(data + i), b += load_lanes<F>(data + i + w);
                c += load_lanes<F>(data + i + 2 * w), d += load_lanes<F>(data + i + 3 * w);
            }
            const F s = (a + b) + (c + d);
            float pass = 0.0f;
            for (std::size_t l = 0; l < lanes<F>; ++l) pass += lane(s, l);
            sum = pass;  // (each pass sums the same; the last one is checked)
        }
        *out = sum;
    };
    const auto [best, median] = best_and_median(
        [&] {
            std::vector<float> sums(threads);
            std::vector<std::thread> pool;
            const std::size_t step = floats / threads / 64 * 64;
            for (unsigned t = 0; t < threads; ++t) pool.emplace_back(part, t * step, (t + 1) * step, &sums[t]);
            for (std::thread& t : pool) t.join();
            keep(sums[0]);
            if (std::fabs(sums[0] - float(step)) > 1e-3f * float(step))
                throw std::runtime_error("limit kernels: the bandwidth read summed wrong");
        },
        runs);
    (void)median;
    return double(floats / threads / 64 * 64 * threads) * sizeof(float) * passes / best / 1e9;
}

}  // namespace

double tsc_ghz() {
    const auto t0 = Clock::now();
    const std::uint64_t c0 = __rdtsc();
    while (seconds_since(t0) < 0.1) {
    }
    const std::uint64_t c1 = __rdtsc();
    return double(c1 - c0) / seconds_since(t0) / 1e9;
}

std::vector<KernelTimes> time_wide_kernels(double ghz) {
    std::vector<KernelTimes> out;
#if XSIMD_WITH_AVX512F
    out.push_back(time_kernels<Float16>(ghz));
#endif
#if XSIMD_WITH_AVX2
    out.push_back(time_kernels<Float8>(ghz));
#endif
    out.push_back(time_kernels<Float4>(ghz));
    return out;
}

Bandwidth measure_bandwidth(std::size_t mib, std::size_t cache_mib) {
    // 1.0 in every float (so the sums check the read), pages touched before the timing.
    const std::size_t floats = mib * 1024 * 1024 / sizeof(float);
    std::unique_ptr<float[], decltype(&std::free)> buf(
        static_cast<float*>(std::aligned_alloc(64, floats * sizeof(float))), &std::free);
    if (!buf) throw std::runtime_error("limit kernels: no memory for the bandwidth buffer");
    std::fill(buf.get(), buf.get() + floats, 1.0f);
    Bandwidth b;
    b.buffer_mib = mib;
    b.gbs_1 = read_bandwidth(buf.get(), floats, 1, 15, 1);
    b.gbs_2 = read_bandwidth(buf.get(), floats, 2, 15, 1);
    // The first cache_mib of it, read 16 times per timing (the untimed first run brings it in):
    // long enough that the threads' start does not count, short enough that on a loaded machine
    // some of the 51 timings run without a preemption.
    b.cache_mib = std::min(cache_mib, mib);
    const std::size_t cache_floats = b.cache_mib * 1024 * 1024 / sizeof(float);
    b.cache_gbs_1 = read_bandwidth(buf.get(), cache_floats, 1, 51, 16);
    b.cache_gbs_2 = read_bandwidth(buf.get(), cache_floats, 2, 51, 16);
    return b;
}

}  // namespace arbor::perf
