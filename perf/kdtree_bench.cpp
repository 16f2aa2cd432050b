// `arbor-bench kdtree`: build time, SAH cost, memory and scalar Mrays/s of the kd-tree on a model and on a
// replicated copy of it, next to Embree's default build of the same triangles (when available).
// Not a test: it validates against brute on a subset of rays first, then times.
//
//   arbor-bench kdtree [--model FILE] [--replicate N] [--repeat R] [--threads T] [--rays N] [--validate N]
//                [--build-only] [--no-embree] [--compare-bvh] [--no-perfect-splits] [--kt K_T] [--exact-below N]
//
// The SIMD paths' layouts of each kd walk (KdBlockConfig::walk: the ropes' leaf blocks, the cells'
// and the tight cells' wide BVH) are timed on the built tree after the build: ms (median of R)
// and MB beside the tree's own.
#include "perf/commands.h"
#include "accel/factory/make_accel.h"
#include "accel/structures/brute_accel.h"
#include "accel/structures/kdtree_accel.h"
#include "accel/kdtree/kdtree_build.h"
#include "accel/util/timer.h"
#include "accel/interface/trace.h"
#include "engine/obj_loader.h"

#ifdef ARBOR_HAVE_EMBREE
#include "embree_peer.h"
#endif

#include <tbb/global_control.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

using namespace arbor;
using accel::Hit;
using accel::Ray;
using accel::Vec3f;

namespace {

struct Options {
    std::string model = ARBOR_SHARED_SCENES "/models/stanford-bunny.obj";
    int replicate = 1;  // copies per axis (N^3 copies)
    int repeat = 5;
    int threads = 2;
    std::size_t rays = 200000;
    std::size_t validate = 2000;
    bool perfect = true;
    float kt = -1.0f, ki = -1.0f;
    bool build_only = false;
    long exact_below = -1;
    bool embree = true;
    bool compare = false;
};

engine::Mesh replicate(const engine::Mesh& m, int n) {
    if (n <= 1) return m;
    engine::Mesh out;
    const Vec3f step = m.bounds.extent() * 1.1f;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) {
                const auto base = std::uint32_t(out.x.size());
                const Vec3f off{step.x * float(i), step.y * float(j), step.z * float(k)};
                for (std::size_t v = 0; v < m.vertex_count(); ++v) {
                    out.x.push_back(m.x[v] + off.x);
                    out.y.push_back(m.y[v] + off.y);
                    out.z.push_back(m.z[v] + off.z);
                }
                for (std::uint32_t idx : m.indices) out.indices.push_back(base + idx);
            }
    out.compute_bounds();
    return out;
}

std::vector<Ray> camera_rays(const accel::Bounds& b, int w, int h) {
    const Vec3f c = b.center();
    const float r = simd::length(b.extent()) * 0.5f;
    const Vec3f eye = c + Vec3f{0.3f, 0.4f, 1.0f} * (2.5f * r);
    const Vec3f fwd = simd::normalize(c - eye);
    const Vec3f right = simd::normalize(simd::cross(fwd, Vec3f{0, 1, 0}));
    const Vec3f up = simd::cross(right, fwd);
    std::vector<Ray> rays;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float px = (float(x) + 0.5f) / float(w) - 0.5f, py = (float(y) + 0.5f) / float(h) - 0.5f;
            rays.push_back({eye, 0.0f, fwd + right * (0.8f * px) - up * (0.8f * py), INFINITY});
        }
    return rays;
}

std::vector<Ray> random_rays(const accel::Bounds& b, std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<Ray> rays(n);
    for (Ray& r : rays) {
        r.org = {b.lo.x + u(rng) * (b.hi.x - b.lo.x), b.lo.y + u(rng) * (b.hi.y - b.lo.y),
                 b.lo.z + u(rng) * (b.hi.z - b.lo.z)};
        r.dir = simd::normalize(Vec3f{g(rng), g(rng), g(rng)});
    }
    return rays;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}


void run(const Options& o, const engine::Mesh& mesh, const char* label) {
    accel::BuildConfig cfg;
    cfg.kd.perfect_splits = o.perfect;
    if (o.kt > 0) cfg.kd.traversal_cost = o.kt;
    if (o.ki > 0) cfg.kd.intersection_cost = o.ki;
    if (o.exact_below >= 0) cfg.kd.exact_below = std::uint32_t(std::min<long>(o.exact_below, 0xFFFFFFFFL));
    std::printf("== %s: %zu triangles, %d threads\n", label, mesh.triangle_count(), o.threads);

    // Builds, interleaved with Embree's so that machine noise hits both alike.
    std::vector<double> kd_ms, em_ms;
    std::unique_ptr<accel::KdTreeAccel> kd;
    for (int r = 0; r < o.repeat; ++r) {
        kd = accel::make_kdtree_accel(mesh.view(), cfg);
        kd_ms.push_back(kd->stats().build_ms);
#ifdef ARBOR_HAVE_EMBREE
        if (o.embree) em_ms.push_back(perf::EmbreePeer(mesh.view()).build_ms());
#endif
    }
    const accel::BuildStats& st = kd->stats();
    const accel::KdTreeStats ks = accel::kd_tree_stats(kd->tree(), cfg.kd.reported_traversal_cost, cfg.kd.intersection_cost);
    std::printf("kdtree build   %9.2f ms (median of %d)  nodes %zu leaves %zu (empty %zu) refs/tri %.2f\n",
                median(kd_ms), o.repeat, st.nodes, st.leaves, ks.empty_leaves,
                double(ks.refs) / double(std::max<std::size_t>(1, kd->tree().tris.size())));
    std::printf("               depth max %u (limit %u) mean %.1f  max leaf %u  SAH %.2f  memory %.1f B/tri  peak %.1f MB\n",
                st.max_depth, kd->tree().depth_limit, st.mean_leaf_depth, ks.max_leaf_size, st.sah_cost,
                st.bytes_per_triangle(), double(st.build_peak_bytes) / 1e6);
#ifdef ARBOR_HAVE_EMBREE
    if (o.embree)
        std::printf("embree build   %9.2f ms (median, default quality)  ratio kdtree/embree %.1f\n", median(em_ms),
                median(kd_ms) / median(em_ms));
#endif
    // The SIMD layout of each walk, made from (a copy of) the built tree: its time and bytes alone.
    const double tree_mb = double(kd->tree().memory_bytes()) / 1e6;
    for (const accel::KdWalk walk : {accel::KdWalk::ropes, accel::KdWalk::cells, accel::KdWalk::tight_cells}) {
        accel::BuildConfig wcfg = cfg;
        wcfg.layouts = accel::Layouts::simd;
        wcfg.kd_blocks.walk = walk;
        std::vector<double> ms;
        std::size_t bytes = 0, peak = 0;
        for (int r = 0; r < o.repeat; ++r) {
            accel::KdTree copy = kd->tree();
            const auto a = accel::make_kdtree_accel(std::move(copy), wcfg, 0.0);
            ms.push_back(a->stats().build_ms);
            bytes = a->stats().memory_bytes - a->tree().memory_bytes();
            peak = a->stats().build_peak_bytes;
        }
        std::printf("layout %-11s %8.2f ms (median of %d)  %.2f MB (tree %.2f MB)  build peak %.1f MB\n",
                    accel::kd_walk_name(walk), median(ms), o.repeat, double(bytes) / 1e6, tree_mb, double(peak) / 1e6);
    }

    if (o.build_only) return;
    const std::vector<Ray> coherent = camera_rays(mesh.bounds, 512, std::max<int>(1, int(o.rays / 512)));
    const std::vector<Ray> incoherent = random_rays(mesh.bounds, o.rays, 7);
    if (o.validate > 0) {
        accel::BruteAccel brute(mesh.view());
        for (const auto* set : {&coherent, &incoherent}) {
            const std::size_t n = std::min(o.validate, set->size());
            std::vector<Ray> sub;
            for (std::size_t i = 0; i < n; ++i) sub.push_back((*set)[i * (set->size() / n)]);
            std::vector<Hit> a(n), b(n), c(n), d(n);
            accel::trace_parallel(*kd, sub, a, accel::Query::closest);
            accel::trace_parallel(brute, sub, b, accel::Query::closest);
            accel::trace_parallel(*kd, sub, c, accel::Query::any);
            std::size_t bad = 0, bad_any = 0;
            for (std::size_t i = 0; i < n; ++i) {
                bad += !accel::hits_agree(a[i], b[i]);
                bad_any += c[i].is_hit() != b[i].is_hit();
            }
            std::printf("validate       %zu rays vs brute: %zu closest and %zu any-hit disagreements\n", n, bad, bad_any);
        }
    }
    // The same rays through bvh-sah's scalar path, interleaved, for context.
    const std::unique_ptr<accel::Accel> bvh = o.compare ? accel::make_accel(accel::AccelKind::bvh_sah, mesh.view()) : nullptr;
    for (const auto& [name, set] : {std::pair{"coherent", &coherent}, std::pair{"incoherent", &incoherent}}) {
        std::vector<Hit> hits(set->size());
        for (const auto q : {accel::Query::closest, accel::Query::any}) {
            std::vector<double> ms, bvh_ms;
            for (int r = 0; r < o.repeat; ++r) {
                const accel::Timer t;
                accel::trace_parallel(*kd, *set, hits, q, accel::TracePath::scalar, 256);
                ms.push_back(t.ms());
                if (!bvh) continue;
                const accel::Timer tb;
                accel::trace_parallel(*bvh, *set, hits, q, accel::TracePath::scalar, 256);
                bvh_ms.push_back(tb.ms());
            }
            std::printf("trace %-10s %-7s %7.2f Mrays/s (median of %d, %zu rays)", name,
                        q == accel::Query::closest ? "closest" : "any", double(set->size()) / median(ms) / 1e3,
                        o.repeat, set->size());
            if (bvh) std::printf("   bvh-sah scalar %7.2f Mrays/s", double(set->size()) / median(bvh_ms) / 1e3);
            std::printf("\n");
        }
    }
}

}  // namespace

static int kdtree_main(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const auto next = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "arbor-bench kdtree: %s: missing value\n", a.c_str());
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--model") o.model = next();
        else if (a == "--replicate") o.replicate = std::stoi(next());
        else if (a == "--repeat") o.repeat = std::max(1, std::stoi(next()));
        else if (a == "--threads") o.threads = std::max(1, std::stoi(next()));
        else if (a == "--rays") o.rays = std::stoul(next());
        else if (a == "--validate") o.validate = std::stoul(next());
        else if (a == "--no-perfect-splits") o.perfect = false;
        else if (a == "--kt") o.kt = std::stof(next());
        else if (a == "--build-only") o.build_only = true;
        else if (a == "--exact-below") o.exact_below = std::stol(next());
        else if (a == "--no-embree") o.embree = false;
        else if (a == "--compare-bvh") o.compare = true;
        else if (a == "--ki") o.ki = std::stof(next());
        else {
            std::fprintf(stderr, "arbor-bench kdtree: unknown option '%s'\n", a.c_str());
            return 2;
        }
    }
    try {
        tbb::global_control threads(tbb::global_control::max_allowed_parallelism, std::size_t(o.threads));
        engine::Warnings warnings;
        const engine::Mesh mesh = engine::load_obj(o.model, warnings);
        const engine::Mesh scene = replicate(mesh, o.replicate);
        run(o, scene, o.replicate > 1 ? "replicated" : o.model.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "arbor-bench kdtree: %s\n", e.what());
        return 1;
    }
    return 0;
}

int arbor::perf::kdtree_command(int argc, char** argv) { return kdtree_main(argc, argv); }
