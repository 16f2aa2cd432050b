// A C interface over fcpw (github.com/rohan-sawhney/fcpw) for the peers benchmark
// (scripts/peers/fcpw_peer.py calls it through ctypes). fcpw is not part of this repository: the
// peer compiles this file against the headers of a checkout given on the command line.
//
// Each query walks the whole batch with `threads` std::threads that take blocks of queries from
// an atomic counter, and calls fcpw's one-query API on each: the same threads for every query.
// fcpw's rays have no tnear and expect unit directions (its own line-of-sight test normalizes),
// so each ray starts at o + tnear d, runs along d / |d| for (tfar - tnear) |d|, and the t it
// reports is mapped back to the caller's parametrization.
#if defined(FCPW_USE_ENOKI) && !defined(FCPW_SIMD_WIDTH)
// The width fcpw's CMakeLists.txt picks from enoki's ISA probe: 16 with AVX-512, 8 with AVX, else 4.
#if defined(__AVX512DQ__)
#define FCPW_SIMD_WIDTH 16
#elif defined(__AVX__)
#define FCPW_SIMD_WIDTH 8
#else
#define FCPW_SIMD_WIDTH 4
#endif
#endif
#include <fcpw/fcpw.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <thread>
#include <vector>

namespace {

using Scene = fcpw::Scene<3>;

// Runs body(i) for i in [0, n) on `threads` threads, blocks of 1024 handed out dynamically.
template <class Body>
void parallel(std::int64_t n, int threads, Body body) {
    constexpr std::int64_t kBlock = 1024;
    std::atomic<std::int64_t> next{0};
    auto work = [&] {
        for (;;) {
            const std::int64_t lo = next.fetch_add(kBlock);
            if (lo >= n) return;
            const std::int64_t hi = std::min(n, lo + kBlock);
            for (std::int64_t i = lo; i < hi; ++i) body(i);
        }
    };
    std::vector<std::thread> pool;
    for (int k = 1; k < threads; ++k) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
}

// The fcpw ray for the caller's ray i, and the length of its direction (t scale).
struct Shifted {
    fcpw::Ray<3> ray;
    float len;
};

Shifted make_ray(const float* o, const float* d, const float* tnear, const float* tfar, std::int64_t i) {
    const fcpw::Vector3 dir(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
    const float len = dir.norm();
    const float tn = tnear[i];
    const fcpw::Vector3 org = fcpw::Vector3(o[3 * i], o[3 * i + 1], o[3 * i + 2]) + tn * dir;
    const float span = std::isfinite(tfar[i]) ? (tfar[i] - tn) * len : fcpw::maxFloat;
    return {fcpw::Ray<3>(org, dir / len, span), len};
}

// Closest hit by `test` (a call of fcpw's on scene, ray and interaction): t in the caller's
// parametrization, +inf on a miss.
template <class Test>
void closest_by(const void* scene, const float* o, const float* d, const float* tnear, const float* tfar,
                std::int64_t n, float* t_out, int threads, Test test) {
    const auto& s = *static_cast<const Scene*>(scene);
    parallel(n, threads, [&](std::int64_t i) {
        Shifted r = make_ray(o, d, tnear, tfar, i);
        fcpw::Interaction<3> hit;
        t_out[i] = test(s, r.ray, hit) ? tnear[i] + hit.d / r.len : std::numeric_limits<float>::infinity();
    });
}

}  // namespace

extern "C" {

// How this shim was built: enoki and its SIMD width, or scalar.
const char* fcpw_config() {
#ifdef FCPW_USE_ENOKI
    static char text[64];
    std::snprintf(text, sizeof text, "enoki, SIMD width %d", FCPW_SIMD_WIDTH);
    return text;
#else
    return "scalar (no enoki)";
#endif
}

// Builds fcpw's scene over float32 (nv, 3) vertices and uint32 (nf, 3) faces: one object, the
// surface-area BVH (fcpw's README default), vectorized when `vectorize` and enoki are on.
void* fcpw_build(const float* verts, std::int64_t nv, const std::uint32_t* faces, std::int64_t nf, int vectorize) {
    auto* scene = new Scene();
    scene->setObjectCount(1);
    std::vector<fcpw::Vector3> positions(static_cast<std::size_t>(nv));
    for (std::int64_t i = 0; i < nv; ++i)
        positions[i] = fcpw::Vector3(verts[3 * i], verts[3 * i + 1], verts[3 * i + 2]);
    std::vector<fcpw::Vector3i> indices(static_cast<std::size_t>(nf));
    for (std::int64_t i = 0; i < nf; ++i)
        indices[i] = fcpw::Vector3i(int(faces[3 * i]), int(faces[3 * i + 1]), int(faces[3 * i + 2]));
    scene->setObjectVertices(positions, 0);
    scene->setObjectTriangles(indices, 0);
    scene->build(fcpw::AggregateType::Bvh_SurfaceArea, vectorize != 0);
    return scene;
}

void fcpw_free(void* scene) { delete static_cast<Scene*>(scene); }

// Closest hit through intersect (Moller-Trumbore).
void fcpw_closest(const void* scene, const float* o, const float* d, const float* tnear, const float* tfar,
                  std::int64_t n, float* t_out, int threads) {
    closest_by(scene, o, d, tnear, tfar, n, t_out, threads,
               [](const Scene& s, auto& ray, fcpw::Interaction<3>& hit) { return s.intersect(ray, hit); });
}

// Closest hit through intersectRobust, fcpw's watertight test (Woop, Benthin and Wald 2013).
void fcpw_closest_robust(const void* scene, const float* o, const float* d, const float* tnear, const float* tfar,
                         std::int64_t n, float* t_out, int threads) {
    closest_by(scene, o, d, tnear, tfar, n, t_out, threads,
               [](const Scene& s, auto& ray, fcpw::Interaction<3>& hit) { return s.intersectRobust(ray, hit); });
}

// Any hit: fcpw's intersect with checkForOcclusion (it stops at the first hit found).
void fcpw_any(const void* scene, const float* o, const float* d, const float* tnear, const float* tfar, std::int64_t n,
              std::uint8_t* out, int threads) {
    const auto& s = *static_cast<const Scene*>(scene);
    parallel(n, threads, [&](std::int64_t i) {
        Shifted r = make_ray(o, d, tnear, tfar, i);
        fcpw::Interaction<3> hit;
        out[i] = s.intersect(r.ray, hit, true) ? 1 : 0;
    });
}

// Crossing count: fcpw's intersect with recordAllHits (hits sorted, duplicates at shared edges
// removed by fcpw).
void fcpw_count(const void* scene, const float* o, const float* d, const float* tnear, const float* tfar,
                std::int64_t n, std::int32_t* out, int threads) {
    const auto& s = *static_cast<const Scene*>(scene);
    parallel(n, threads, [&](std::int64_t i) {
        Shifted r = make_ray(o, d, tnear, tfar, i);
        std::vector<fcpw::Interaction<3>> hits;
        out[i] = s.intersect(r.ray, hits, false, true);
    });
}

// Distance from each point to the mesh (findClosestPoint, no radius bound).
void fcpw_closest_point(const void* scene, const float* p, std::int64_t n, float* dist, int threads) {
    const auto& s = *static_cast<const Scene*>(scene);
    parallel(n, threads, [&](std::int64_t i) {
        fcpw::Interaction<3> hit;
        const fcpw::Vector3 x(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
        dist[i] = s.findClosestPoint(x, hit) ? hit.d : std::numeric_limits<float>::infinity();
    });
}

// Inside: fcpw's contains (odd crossing counts along +x and along +y).
void fcpw_inside(const void* scene, const float* p, std::int64_t n, std::uint8_t* out, int threads) {
    const auto& s = *static_cast<const Scene*>(scene);
    parallel(n, threads,
             [&](std::int64_t i) { out[i] = s.contains(fcpw::Vector3(p[3 * i], p[3 * i + 1], p[3 * i + 2])) ? 1 : 0; });
}

}  // extern "C"
