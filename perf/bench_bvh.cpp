// `arbor-bench bvh`: build time, SAH cost and scalar trace speed of the BVH builders on one model and on
// that model replicated on a grid (millions of triangles). A benchmark, not a test: it validates
// every structure against brute on a subset of the rays first, then times. Usage:
//   arbor-bench bvh [--model OBJ] [--copies N] [--repeat K] [--threads T] [--rays N] [--sweep-max N] [--build-only 1]
//             [--only bvh-sah,lbvh]
// Times are medians of K runs; the builders (and Embree's default build, rtcCommitScene at
// RTC_BUILD_QUALITY_MEDIUM, when the peer is built) are run interleaved (A B C A B C ...) so that
// machine noise hits them alike; ratios to Embree are medians of the per-round ratios.
#include "perf/commands.h"
#include "accel/factory/make_accel.h"
#include "accel/interface/accel.h"
#include "accel/structures/brute_accel.h"
#include "accel/structures/bvh_accel.h"
#include "accel/bvh/bvh_build.h"
#include "accel/util/timer.h"
#include "accel/interface/trace.h"
#include "engine/obj_loader.h"
#include "engine/ray_gen.h"
#if ARBOR_HAVE_EMBREE
#include "perf/embree_peer.h"
#endif

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <string>
#include <vector>

using namespace arbor;
using accel::Vec3f;

namespace {

struct Options {
    std::string model = ARBOR_SHARED_SCENES "/models/stanford-bunny.obj";
    std::string only;  ///< comma-separated structure names to run (empty: all four)
    int copies = 36, repeat = 5, threads = 2;
    std::size_t rays = 1u << 18, sweep_max = 200000;
    bool build_only = false;  ///< only the bvh-sah phases (for profiling)
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

/// `copies` copies of `m` on a square grid in x/z, spaced 1.2 model sizes apart.
engine::Mesh replicate(const engine::Mesh& m, int copies) {
    engine::Mesh out;
    const int side = int(std::ceil(std::sqrt(double(copies))));
    const Vec3f e = m.bounds.extent();
    for (int c = 0; c < copies; ++c) {
        const Vec3f shift{float(c % side) * 1.2f * e.x, 0.0f, float(c / side) * 1.2f * e.z};
        const auto base = std::uint32_t(out.vertex_count());
        for (std::size_t i = 0; i < m.vertex_count(); ++i) out.add_vertex(Vec3f{m.x[i], m.y[i], m.z[i]} + shift);
        for (std::uint32_t i : m.indices) out.indices.push_back(base + i);
    }
    out.compute_bounds();
    return out;
}

struct RaySet {
    std::string name;
    std::vector<accel::Ray> rays;
};

std::vector<RaySet> make_rays(const engine::Mesh& mesh, std::size_t n) {
    engine::RayGenScene gs{mesh.view(), mesh.bounds, mesh.bounds.hi + mesh.bounds.extent(), std::nullopt};
    std::vector<RaySet> sets;
    for (auto kind : {engine::RayKind::primary, engine::RayKind::random}) {
        engine::RayGenConfig cfg;
        cfg.kind = kind;
        cfg.count = n;
        sets.push_back({std::string(engine::to_string(kind)), engine::generate_rays(gs, cfg)});
    }
    return sets;
}

/// Rays of `sets` (a spread-out subset of `per_set` each) traced by `a` and by brute must agree.
std::size_t validate(const accel::Accel& a, const accel::BruteAccel& brute, const std::vector<RaySet>& sets, std::size_t per_set) {
    std::size_t bad = 0;
    for (const auto& s : sets) {
        std::vector<accel::Ray> sub;
        const std::size_t step = std::max<std::size_t>(1, s.rays.size() / per_set);
        for (std::size_t i = 0; i < s.rays.size(); i += step) sub.push_back(s.rays[i]);
        std::vector<accel::Hit> ref(sub.size()), got(sub.size()), any(sub.size());
        accel::trace_parallel(brute, sub, ref, accel::Query::closest, accel::TracePath::scalar, 4);
        accel::trace_parallel(a, sub, got, accel::Query::closest, accel::TracePath::scalar);
        accel::trace_parallel(a, sub, any, accel::Query::any, accel::TracePath::scalar);
        for (std::size_t i = 0; i < sub.size(); ++i) bad += !accel::hits_agree(ref[i], got[i]) + (any[i].is_hit() != ref[i].is_hit());
    }
    return bad;
}

void run_scene(const std::string& name, const engine::Mesh& mesh, const Options& o) {
    const auto view = mesh.view();
    std::printf("\n## %s: %zu triangles, %d threads, median of %d\n", name.c_str(), mesh.triangle_count(), o.threads, o.repeat);
    const accel::BuildConfig cfg;
    const std::vector<std::pair<std::string, accel::AccelKind>> kinds = {
        {"bvh-median", accel::AccelKind::bvh_median}, {"bvh-sah", accel::AccelKind::bvh_sah},
        {"lbvh", accel::AccelKind::lbvh}, {"kdtree", accel::AccelKind::kdtree}};
    // Each structure is built twice per round: with the scalar layout only (the structure of its
    // reference path) and with the SIMD layout only (what `arbor trace` builds for its default path).
    accel::BuildConfig scalar_cfg = cfg, simd_cfg = cfg;
    scalar_cfg.layouts = accel::Layouts::scalar;
    simd_cfg.layouts = accel::Layouts::simd;
    std::map<std::string, std::vector<double>> times, times_simd;
    std::map<std::string, std::unique_ptr<accel::Accel>> built;
    std::vector<double> t_refs, t_build, t_scalar, t_simd;
    std::vector<double> t_embree;
    std::map<std::string, std::vector<double>> ratio, ratio_simd;  // per round: build ms / Embree's build ms
#if ARBOR_HAVE_EMBREE
    std::unique_ptr<perf::EmbreePeer> embree;
#endif
    for (int r = 0; r < o.repeat; ++r) {
#if ARBOR_HAVE_EMBREE
        embree.reset();
        embree = std::make_unique<perf::EmbreePeer>(view);
        t_embree.push_back(embree->build_ms());
#endif
        for (const auto& [kname, kind] : kinds) {
            if (o.build_only) break;
            if (!o.only.empty() && ("," + o.only + ",").find("," + kname + ",") == std::string::npos) continue;
            try {
                const accel::Timer t;
                auto a = accel::make_accel(kind, view, scalar_cfg);
                times[kname].push_back(t.ms());
                if (!t_embree.empty()) ratio[kname].push_back(times[kname].back() / t_embree.back());
                built[kname] = std::move(a);
                const accel::Timer ts;
                auto b = accel::make_accel(kind, view, simd_cfg);
                times_simd[kname].push_back(ts.ms());
                if (!t_embree.empty()) ratio_simd[kname].push_back(times_simd[kname].back() / t_embree.back());
            } catch (const std::invalid_argument&) {  // not in this build yet
            }
        }
        // bvh-sah by phases: prim refs, binned SAH build, conversion to each traversal layout.
        const accel::Timer t0;
        const accel::PrimRefs refs = accel::make_prim_refs(view);
        const double a = t0.ms();
        accel::BinaryBvh bvh = accel::build_bvh_sah(refs, cfg.bvh);
        const double b = t0.ms();
        accel::BinaryBvh copy = bvh;
        const accel::Timer t1;
        const auto acc = accel::make_bvh_accel(accel::AccelKind::bvh_sah, std::move(bvh), view, scalar_cfg, 0.0);
        const double c = t1.ms();
        const accel::Timer t2;
        const auto acc2 = accel::make_bvh_accel(accel::AccelKind::bvh_sah, std::move(copy), view, simd_cfg, 0.0);
        t_refs.push_back(a), t_build.push_back(b - a), t_scalar.push_back(c), t_simd.push_back(t2.ms());
    }
    std::printf("bvh-sah phases: prim refs %.1f ms, binned SAH %.1f ms, scalar layout %.1f ms, SIMD layout %.1f ms\n",
                median(t_refs), median(t_build), median(t_scalar), median(t_simd));
    if (o.build_only) return;

    const auto sets = make_rays(mesh, o.rays);
    const accel::BruteAccel brute(view);
    const std::size_t check = std::max<std::size_t>(16, std::size_t(2e8 / double(mesh.triangle_count()) / 2));
    std::printf("| structure | build ms, scalar layout | / Embree's | build ms, SIMD layout | / Embree's | SAH cost | nodes | depth | B/tri (scalar layout) | brute disagreements (%zu rays) |",
                std::min(check, o.rays) * 2);
    for (const auto& s : sets) std::printf(" %s Mrays/s |", s.name.c_str());
    std::printf("\n|---|---|---|---|---|---|---|---|---|---|");
    for (std::size_t i = 0; i < sets.size(); ++i) std::printf("---|");
    std::printf("\n");
    for (const auto& [kname, kind] : kinds) {
        if (!built.count(kname)) continue;
        const accel::Accel& a = *built[kname];
        const std::size_t bad = validate(a, brute, sets, check);
        std::printf("| %s | %.1f | %s | %.1f | %s | %.2f | %zu | %u | %.1f | %zu |", kname.c_str(), median(times[kname]),
                    ratio.count(kname) ? std::to_string(median(ratio[kname])).substr(0, 4).c_str() : "-",
                    median(times_simd[kname]),
                    ratio_simd.count(kname) ? std::to_string(median(ratio_simd[kname])).substr(0, 4).c_str() : "-",
                    a.stats().sah_cost, a.stats().nodes, a.stats().max_depth, a.stats().bytes_per_triangle(), bad);
        for (const auto& s : sets) {
            std::vector<accel::Hit> hits(s.rays.size());
            std::vector<double> tt;
            for (int r = 0; r < o.repeat; ++r) {
                const accel::Timer t;
                accel::trace_parallel(a, s.rays, hits, accel::Query::closest, accel::TracePath::scalar);
                tt.push_back(t.ms());
            }
            std::printf(" %.2f |", double(s.rays.size()) / median(tt) * 1e-3);
        }
        std::printf("\n");
    }
#if ARBOR_HAVE_EMBREE
    std::printf("| embree (medium, %s) | %.1f | 1 | %.1f | 1 | - | - | - | %.1f | - |", perf::embree_config_name(embree->config()).c_str(),
                median(t_embree), median(t_embree), double(embree->memory_bytes()) / double(mesh.triangle_count()));
    for (const auto& s : sets) {
        std::vector<accel::Hit> hits(s.rays.size());
        std::vector<double> tt;
        for (int r = 0; r < o.repeat; ++r) {
            const accel::Timer t;
            embree->trace_parallel(s.rays, hits, accel::Query::closest, perf::EmbreeCall::single, s.name == "primary");
            tt.push_back(t.ms());
        }
        std::printf(" %.2f |", double(s.rays.size()) / median(tt) * 1e-3);
    }
    std::printf("\n");
#else
    std::printf("(Embree peer not built: no Embree row)\n");
#endif
    if (mesh.triangle_count() <= o.sweep_max) {
        const accel::Timer t;
        const accel::BinaryBvh sweep = accel::build_bvh_sah_sweep(accel::make_prim_refs(view), cfg.bvh);
        const double ms = t.ms();
        const double sweep_cost = accel::bvh_tree_stats(sweep).sah_cost;
        std::printf("full-sweep SAH: cost %.2f (built in %.0f ms); bvh-sah / sweep = %.4f\n", sweep_cost, ms,
                    built.count("bvh-sah") ? built["bvh-sah"]->stats().sah_cost / sweep_cost : 0.0);
        // The tree of the SIMD-only build stops at the layout's width (BvhBuildConfig::leaf_floor):
        // compared with a full sweep under the same floor.
        accel::BuildConfig floor_cfg = cfg;
        floor_cfg.layouts = accel::Layouts::simd;
        floor_cfg.bvh.leaf_floor = accel::bvh_leaf_floor(floor_cfg);
        const accel::PrimRefs refs = accel::make_prim_refs(view);
        const double binned_floor = accel::bvh_tree_stats(accel::build_bvh_sah(refs, floor_cfg.bvh)).sah_cost;
        const double sweep_floor = accel::bvh_tree_stats(accel::build_bvh_sah_sweep(refs, floor_cfg.bvh)).sah_cost;
        std::printf("with leaf floor %u (the SIMD-only build): bvh-sah cost %.2f, full sweep %.2f; bvh-sah / sweep = %.4f\n",
                    floor_cfg.bvh.leaf_floor, binned_floor, sweep_floor, binned_floor / sweep_floor);
    }
}

}  // namespace

static int bvh_main(int argc, char** argv) {
    Options o;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string k = argv[i], v = argv[i + 1];
        if (k == "--model") o.model = v;
        else if (k == "--copies") o.copies = std::atoi(v.c_str());
        else if (k == "--repeat") o.repeat = std::max(1, std::atoi(v.c_str()));
        else if (k == "--threads") o.threads = std::max(1, std::atoi(v.c_str()));
        else if (k == "--rays") o.rays = std::size_t(std::atoll(v.c_str()));
        else if (k == "--build-only") o.build_only = v != "0";
        else if (k == "--only") o.only = v;
        else if (k == "--sweep-max") o.sweep_max = std::size_t(std::atoll(v.c_str()));
        else {
            std::fprintf(stderr, "arbor-bench bvh: unknown option %s\n", k.c_str());
            return 2;
        }
    }
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(o.threads));
    engine::Warnings w;
    engine::Mesh model;
    try {
        model = engine::load_obj(o.model, w);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "arbor-bench bvh: %s\n", e.what());
        return 1;
    }
    run_scene(o.model.substr(o.model.find_last_of('/') + 1), model, o);
    if (o.copies > 1) run_scene("replicated x" + std::to_string(o.copies), replicate(model, o.copies), o);
    return 0;
}

int arbor::perf::bvh_command(int argc, char** argv) { return bvh_main(argc, argv); }
