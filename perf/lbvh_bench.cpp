// `arbor-bench lbvh`: the LBVH build compared with itself (hierarchy method, code width, digit width),
// with the top-down builders and (when built with it) Embree's default build, on the bunny and on
// the bunny replicated to millions of triangles, at 1 and 2 threads. Builds are timed interleaved
// (variant order rotates every repetition) and reported as medians; then each variant's SAH cost
// and scalar trace speed (primary and random rays, all threads) are printed. Not a test.
#include "perf/commands.h"
#include "accel/factory/make_accel.h"
#include "accel/structures/brute_accel.h"
#include "accel/structures/bvh_accel.h"
#include "accel/bvh/bvh_build.h"
#include "accel/lbvh/lbvh_build.h"
#include "accel/util/timer.h"
#include "accel/interface/trace.h"
#include "engine/obj_loader.h"
#include "engine/ray_gen.h"
#ifdef ARBOR_HAVE_EMBREE
#include "embree_peer.h"
#endif

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <string>
#include <vector>

using namespace arbor;
using accel::Vec3f;

namespace {

struct Variant {
    std::string name;
    bool is_lbvh = false;
    accel::LbvhOptions lbvh;
    accel::BvhBuilder builder = nullptr;  ///< top-down builders
    bool embree = false;
};

struct Sample {
    double total_ms = 0;      ///< prim refs + builder + traversal layout (what make_accel times)
    double refs_ms = 0, layout_ms = 0;
    accel::LbvhTimings steps;
};

/// The 1-minute load average (the machine is shared: read timings against it).
std::string load_average() {
    std::FILE* f = std::fopen("/proc/loadavg", "r");
    if (!f) return "?";
    char buf[64] = {};
    const bool ok = std::fgets(buf, sizeof buf, f) != nullptr;
    std::fclose(f);
    std::string s = ok ? buf : "?";
    return s.substr(0, s.find(' '));
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

/// The mesh copied on a grid (spacing 1.1 x its extent), `copies` times.
engine::Mesh replicate(const engine::Mesh& m, int copies) {
    engine::Mesh out;
    const int side = int(std::ceil(std::cbrt(double(copies))));
    const Vec3f step = m.bounds.extent() * 1.1f;
    for (int c = 0; c < copies; ++c) {
        engine::Mesh copy = m;
        const Vec3f off{step.x * float(c % side), step.y * float((c / side) % side), step.z * float(c / (side * side))};
        for (std::size_t i = 0; i < copy.vertex_count(); ++i) copy.x[i] += off.x, copy.y[i] += off.y, copy.z[i] += off.z;
        out.append(copy);
    }
    out.material.clear();
    out.materials.clear();
    out.compute_bounds();
    return out;
}

/// Traversal layouts the builds make (--layouts; the scalar trace columns need `all` or `scalar`).
accel::Layouts g_layouts = accel::Layouts::all;

/// One timed build of `v`; returns the Accel (nullptr for Embree) and fills `s`.
std::unique_ptr<accel::Accel> build_once(const Variant& v, const accel::TriangleView& tris, Sample& s) {
    accel::BuildConfig cfg;
    cfg.layouts = g_layouts;
#ifdef ARBOR_HAVE_EMBREE
    if (v.embree) {
        perf::EmbreePeer peer(tris);
        s.total_ms = peer.build_ms();
        return nullptr;
    }
#endif
    const accel::Timer total;
    accel::Timer step;
    accel::BinaryBvh bvh;
    {
        const accel::PrimRefs refs = accel::make_prim_refs(tris);
        s.refs_ms = step.ms();
        bvh = v.is_lbvh ? accel::build_lbvh(refs, cfg.bvh, v.lbvh, &s.steps) : v.builder(refs, cfg.bvh);
    }
    const double build_ms = total.ms();
    step = accel::Timer();
    auto accel = accel::make_bvh_accel(accel::AccelKind::lbvh, std::move(bvh), tris, cfg, build_ms);
    s.layout_ms = step.ms();
    s.total_ms = total.ms();
    return accel;
}

double mrays_per_s(const accel::Accel& a, const std::vector<accel::Ray>& rays, int repeat) {
    std::vector<accel::Hit> hits(rays.size());
    std::vector<double> ms;
    for (int r = 0; r < repeat; ++r) {
        const accel::Timer t;
        accel::trace_parallel(a, rays, hits, accel::Query::closest, accel::TracePath::scalar);
        ms.push_back(t.ms());
    }
    return double(rays.size()) / (median(ms) * 1e3);
}

void run_scene(const std::string& name, const engine::Mesh& mesh, const std::vector<Variant>& variants,
               const std::vector<int>& threads, int repeat, std::size_t ray_count, bool trace) {
    const accel::TriangleView tris = mesh.view();
    std::printf("\n## %s: %zu triangles\n", name.c_str(), mesh.triangle_count());
    for (int nt : threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(nt));
        std::map<std::string, std::vector<Sample>> samples;
        for (int r = 0; r < repeat; ++r)
            for (std::size_t k = 0; k < variants.size(); ++k) {  // rotate the order every repetition
                const Variant& v = variants[(k + std::size_t(r)) % variants.size()];
                Sample s;
                build_once(v, tris, s);
                samples[v.name].push_back(s);
            }
        std::printf("\n### %d thread%s (build: median of %d, interleaved)\n\n", nt, nt > 1 ? "s" : "", repeat);
        std::printf("| variant | build ms | min | refs | codes | sort | hierarchy | layout | SAH cost | nodes | max depth |\n");
        std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (const Variant& v : variants) {
            const auto& ss = samples[v.name];
            auto med = [&](auto get) {
                std::vector<double> x;
                for (const Sample& s : ss) x.push_back(get(s));
                return median(x);
            };
            const double total = med([](const Sample& s) { return s.total_ms; });
            double fastest = 1e300;
            for (const Sample& x : ss) fastest = std::min(fastest, x.total_ms);
            if (v.embree) {
                std::printf("| %s | %.1f | %.1f | | | | | | | | |\n", v.name.c_str(), total, fastest);
                continue;
            }
            Sample s;
            const auto accel = build_once(v, tris, s);
            const auto& st = accel->stats();
            std::printf("| %s | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.2f | %zu | %u |\n", v.name.c_str(), total, fastest,
                        med([](const Sample& x) { return x.refs_ms; }), med([](const Sample& x) { return x.steps.codes_ms; }),
                        med([](const Sample& x) { return x.steps.sort_ms; }),
                        med([](const Sample& x) { return x.steps.hierarchy_ms; }),
                        med([](const Sample& x) { return x.layout_ms; }), st.sah_cost, st.nodes, st.max_depth);
        }
    }
    if (!trace) return;
    // Trace speed at the largest thread count; rays from engine/ray_gen (deterministic).
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads.back()));
    engine::Scene scene = engine::scene_from_mesh(mesh, name);
    const engine::RayGenScene rs = engine::ray_gen_scene(scene);
    engine::RayGenConfig rc;
    rc.count = ray_count;
    const auto primary = engine::generate_rays(rs, rc);
    rc.kind = engine::RayKind::random;
    const auto random = engine::generate_rays(rs, rc);
    std::printf("\n### scalar trace, %d threads, %zu rays per kind (closest hit; median of 3)\n\n", threads.back(), ray_count);
    std::printf("| variant | primary Mrays/s | random Mrays/s | disagreements vs first |\n|---|---|---|---|\n");
    std::vector<accel::Hit> ref_p, ref_r;
    for (const Variant& v : variants) {
        if (v.embree) continue;
        Sample s;
        const auto accel = build_once(v, tris, s);
        std::vector<accel::Hit> hp(primary.size()), hr(random.size());
        accel::trace_parallel(*accel, primary, hp, accel::Query::closest, accel::TracePath::scalar);
        accel::trace_parallel(*accel, random, hr, accel::Query::closest, accel::TracePath::scalar);
        std::size_t bad = 0;
        if (ref_p.empty()) ref_p = hp, ref_r = hr;
        for (std::size_t i = 0; i < hp.size(); ++i) bad += !accel::hits_agree(hp[i], ref_p[i]);
        for (std::size_t i = 0; i < hr.size(); ++i) bad += !accel::hits_agree(hr[i], ref_r[i]);
        std::printf("| %s | %.2f | %.2f | %zu |\n", v.name.c_str(), mrays_per_s(*accel, primary, 3),
                    mrays_per_s(*accel, random, 3), bad);
    }
}

}  // namespace

static int lbvh_main(int argc, char** argv) {
    CLI::App app{"arbor-bench lbvh: LBVH build variants vs bvh-sah, bvh-median and Embree"};
    std::string model = std::string(ARBOR_SHARED_SCENES) + "/models/stanford-bunny.obj";
    int copies = 36, repeat = 5;
    std::vector<int> threads{1, 2};
    std::size_t rays = 1u << 18;
    bool all_variants = false, no_trace = false;
    std::string only;
    app.add_option("--model", model, "OBJ file")->capture_default_str();
    app.add_option("--copies", copies, "copies of the model in the big scene (0: skip it)")->capture_default_str();
    app.add_option("--repeat", repeat, "timed builds per variant")->check(CLI::Range(1, 1000))->capture_default_str();
    app.add_option("--threads", threads, "thread counts")->capture_default_str();
    app.add_option("--rays", rays, "rays per kind for the trace speed")->capture_default_str();
    app.add_flag("--all", all_variants, "every LBVH variant (hierarchy x bits x digits), not only the main ones");
    app.add_flag("--no-trace", no_trace, "build times only");
    std::string layouts = "all";
    app.add_option("--layouts", layouts, "traversal layouts built: all, scalar, simd (what arbor trace builds by default)")
        ->check(CLI::IsMember({"all", "scalar", "simd"}))
        ->capture_default_str();
    app.add_option("--only", only, "run only the variants whose name contains this");
    CLI11_PARSE(app, argc, argv);

    engine::Warnings warnings;
    engine::Mesh mesh;
    try {
        mesh = engine::load_obj(model, warnings);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
    std::vector<Variant> variants;
    for (auto method : {accel::RadixTreeMethod::top_down, accel::RadixTreeMethod::karras})
        for (auto codes : {accel::MortonSort::bits30, accel::MortonSort::bits63, accel::MortonSort::bits63_refined})
            for (int digits : {8, 11}) {
                if (!all_variants && digits != 8) continue;
                Variant v;
                v.is_lbvh = true;
                v.lbvh = {method, codes, digits};
                v.name = std::string("lbvh-") + (method == accel::RadixTreeMethod::karras ? "karras" : "topdown") +
                         (codes == accel::MortonSort::bits30 ? "-30b" : codes == accel::MortonSort::bits63 ? "-63b" : "-63r") +
                         "-d" + std::to_string(digits);
                variants.push_back(v);
                if (codes == accel::MortonSort::bits63_refined && digits == 8) {
                    v.lbvh.sah_collapse = true;
                    v.name += "-sah";
                    variants.push_back(v);
                }
            }
    variants.push_back({"bvh-sah", false, {}, accel::build_bvh_sah, false});
    variants.push_back({"bvh-median", false, {}, accel::build_bvh_median, false});
#ifdef ARBOR_HAVE_EMBREE
    variants.push_back({"embree-medium", false, {}, nullptr, true});
#endif
    if (!only.empty())
        variants.erase(std::remove_if(variants.begin(), variants.end(),
                                      [&](const Variant& v) { return v.name.find(only) == std::string::npos; }),
                       variants.end());
    std::printf("# arbor-bench lbvh: %s, copies %d, repeat %d, load average %s\n", model.c_str(), copies, repeat,
                load_average().c_str());
    g_layouts = layouts == "scalar" ? accel::Layouts::scalar : layouts == "simd" ? accel::Layouts::simd : accel::Layouts::all;
    run_scene("model", mesh, variants, threads, repeat, rays, !no_trace);
    if (copies > 0) run_scene("replicated x" + std::to_string(copies), replicate(mesh, copies), variants, threads, repeat, rays, !no_trace);
    std::printf("\nload average at the end: %s\n", load_average().c_str());
    return 0;
}

int arbor::perf::lbvh_command(int argc, char** argv) { return lbvh_main(argc, argv); }
