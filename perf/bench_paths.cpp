// `arbor-bench paths`: arbor's traversal paths (scalar, single, packet, best) at each BVH width against
// Embree's calls (rtcIntersect1/8/16, and 1M under Embree 3) on the very same .rays files, in one run. A benchmark,
// not a test: every configuration is first checked against the structure's scalar path on all
// rays (and Embree against it too), then all configurations are timed round-robin (the order
// rotated each repeat) so that machine noise hits them alike; medians of --repeats.
//
//   arbor-bench paths --rays DIR [--models DIR] [--scenes a,b] [--kinds primary,shadow,diffuse,random]
//               [--structures bvh-sah,...] [--widths 4,8,16] [--paths scalar,single,packet,best]
//               [--threads 2] [--repeats 5] [--merges 0,8,...] [--floors 0,1] [--shared-leaves 0,32] [--kd-walks ropes,cells,tight]
//               [--kd-kts 12,4] [--cpu-time] [--min-ms 0] [-o OUT.md]
//
// Each structure is built once with the scalar layout only (its scalar path, the reference) and
// once per variant with the SIMD layouts only (the other paths), as `arbor trace` builds them.
//
// DIR/<scene>-<kind>.rays are written by `arbor rays --scene MODEL.obj --kind KIND` (see
// scripts/bench_vs_embree.sh). Shadow rays are any-hit queries, the others closest hit; Embree
// gets the coherent flag for primary and shadow rays, as in `arbor-bench bench`.
#include "perf/commands.h"
#include "accel/factory/make_accel.h"
#include "accel/interface/accel.h"
#include "accel/structures/brute_accel.h"
#include "accel/structures/bvh_accel.h"
#include "accel/util/timer.h"
#include "accel/interface/trace.h"
#include "engine/builtin_scenes.h"
#include "engine/error.h"
#include "engine/obj_loader.h"
#include "engine/rayfile.h"
#include "perf/paths_report.h"

#ifdef ARBOR_HAVE_EMBREE
#include "perf/embree_peer.h"
#endif

#include <CLI/CLI.hpp>
#include <ctime>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

using namespace arbor;

namespace {

struct Options {
    std::string rays_dir, models = ARBOR_SHARED_SCENES "/models", out;
    std::vector<std::string> scenes{"stanford-bunny", "beast", "rocker-arm"};
    std::vector<std::string> kinds{"primary", "shadow", "diffuse", "random"};
    /// Views per scene (scripts/bench_heldout.sh): files DIR/<scene>-<view>-<kind>.rays, each view
    /// its own cell "scene/view"; none: DIR/<scene>-<kind>.rays.
    std::vector<std::string> views;
    std::vector<std::string> structures{"bvh-sah"};
    std::vector<std::string> paths{"scalar", "single", "packet", "best"};
    std::vector<int> widths{0};
    int threads = 2, repeats = 5;
    std::vector<std::uint32_t> merges{0};
    /// Values of BuildConfig::bvh.simd_leaf_floor. The SIMD paths run on a build of the SIMD layouts
    /// only, as `arbor trace` makes it (0: the leaf floor of that build; 1: the fine tree), the
    /// scalar path on a build of the scalar layout only.
    std::vector<std::uint32_t> floors{0};
    std::vector<std::uint32_t> shared{32};
    std::vector<int> switches{-1}, switches_mixed{-1};
    /// The kd-tree's SIMD walks (KdBlockConfig::walk) and SAH traversal costs of its build
    /// (KdBuildConfig::traversal_cost; 0 = the default) of the SIMD builds; other structures ignore them.
    std::vector<std::string> kd_walks{"default"};
    std::vector<float> kd_kts{0.0f};
    std::uint32_t packet_lanes = 0;
    bool embree = true;
    /// Time by the process's CPU time divided by the thread count instead of the wall clock: on a
    /// machine shared with other jobs a preempted thread stretches the wall time of a run (often 2x
    /// on 2 cores), not its CPU time. (TBB's idle spinning counts too, for arbor and Embree alike.)
    bool cpu_time = false;
    /// One timed sample repeats the pass over the file until this many ms (wall clock) have
    /// passed and takes the time per pass: a pass of 131,072 coherent rays lasts ~3 ms on 2
    /// threads, short enough for a thread's wake-up or one preemption to move it by 2x.
    double min_ms = 0;
    std::size_t brute_sample = 256;
};

/// CPU time of the whole process in ms: with --cpu-time (one thread) it does not count the time
/// other jobs on a loaded machine take the core away.
double cpu_ms() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t m = v.size() / 2;
    return v.empty() ? 0.0 : (v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]));
}

/// One timed configuration.
struct Config {
    std::string structure, path;  ///< e.g. "bvh-sah/w16", "single"; Embree: "embree", "1M"
    std::function<void(std::span<const accel::Ray>, std::span<accel::Hit>)> trace;
    bool embree = false;
    std::vector<double> ms;
    long long err = -1;        ///< disagreements with the structure's scalar path (Embree: with the first arbor scalar)
    long long err_brute = -1;  ///< disagreements with brute on a sample of the rays
    long long err_embree = -1; ///< disagreements with Embree's rtcIntersect1 (arbor configurations)
};

bool agree(const accel::Hit& a, const accel::Hit& b, bool any) { return any ? a.is_hit() == b.is_hit() : accel::hits_agree(a, b); }

/// K_T as written in a configuration's name ("12", "1.5").
std::string fmt_kt(float kt) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", double(kt));
    return buf;
}

/// A built structure's SIMD layout, for the report.
struct LayoutRow {
    std::string scene, structure;
    std::size_t triangles = 0, width = 0, nodes = 0, leaves = 0;
    double wide_bytes_per_tri = 0, all_bytes_per_tri = 0, build_ms = 0;
};


#ifdef ARBOR_HAVE_EMBREE
using Peer = perf::EmbreePeer;
#else
struct Peer {};  ///< no Embree peer in this build
#endif

/// The structures of one scene: per --structures name, a scalar-only build (the reference of its
/// structure, read for the scalar path only), then a SIMD-only build per combination of the
/// build options.
struct Structures {
    std::vector<std::unique_ptr<accel::Accel>> built;
    std::vector<std::string> names;
    std::vector<bool> reference;  ///< the scalar-only build of its structure
};

/// One SIMD-only build's settings.
struct SimdVariant {
    int width, sw, swx;
    std::uint32_t merge, floor, shared;
    std::string walk;
    float kt;
};

accel::BuildConfig simd_config(const Options& o, const SimdVariant& v) {
    accel::BuildConfig cfg;
    if (v.walk == "ropes") cfg.kd_blocks.walk = accel::KdWalk::ropes;
    else if (v.walk == "cells") cfg.kd_blocks.walk = accel::KdWalk::cells;
    else if (v.walk == "tight") cfg.kd_blocks.walk = accel::KdWalk::tight_cells;
    else if (v.walk != "default") throw engine::InputError("--kd-walks: ropes, cells, tight or default, not '" + v.walk + "'");
    if (v.kt > 0.0f) cfg.kd.traversal_cost = v.kt;
    cfg.layouts = accel::Layouts::simd;
    cfg.bvh.simd_leaf_floor = v.floor;
    cfg.wide.width = std::uint32_t(v.width);
    cfg.wide.merge_triangles = v.merge;
    cfg.wide.shared_leaf_triangles = v.shared;
    cfg.packets.switch_lanes = v.sw;
    cfg.packets.switch_mixed = v.swx;
    cfg.packets.lanes = o.packet_lanes;
    return cfg;
}

/// The configuration's name in the report: the structure, then what differs from the defaults.
std::string variant_name(const Options& o, const std::string& s, bool kd, const SimdVariant& v) {
    std::string name = s;
    if (v.width || v.merge || v.sw >= 0 || v.swx >= 0) name += "/w" + std::to_string(v.width);
    if (v.merge) name += "m" + std::to_string(v.merge);
    if (v.sw >= 0) name += "s" + std::to_string(v.sw);
    if (v.swx >= 0) name += "x" + std::to_string(v.swx);
    if (o.floors.size() > 1 || v.floor != 0) name += (name == s ? "/f" : "f") + std::to_string(v.floor);
    if (o.shared.size() > 1 || v.shared != 32) name += (name == s ? "/L" : "L") + std::to_string(v.shared);
    if (kd && v.walk != "default") name += (name == s ? "/" : "-") + v.walk;
    if (kd && v.kt > 0.0f) name += "kt" + fmt_kt(v.kt);
    return name;
}

Structures build_structures(const Options& o, const std::string& scene, const accel::TriangleView& tris,
                            std::vector<LayoutRow>& layouts) {
    Structures st;
    for (const std::string& s : o.structures) {
        const auto kind = accel::parse_accel_kind(s);
        if (!kind || *kind == accel::AccelKind::automatic) throw engine::InputError("--structures: unknown structure '" + s + "'");
        accel::BuildConfig scalar_cfg;  // the reference: first of its structure, read for the scalar path only
        scalar_cfg.layouts = accel::Layouts::scalar;
        st.built.push_back(accel::make_accel(*kind, tris, scalar_cfg));
        st.names.push_back(s);
        st.reference.push_back(true);
        const bool kd = *kind == accel::AccelKind::kdtree;
        for (const int width : o.widths)
            for (const std::uint32_t merge : o.merges)
                for (const int sw : o.switches)
                for (const int swx : o.switches_mixed)
                for (const std::uint32_t floor : o.floors)
                for (const std::uint32_t shared : o.shared)
                for (const std::string& walk : o.kd_walks)
                for (const float kt : o.kd_kts) {
                    if (!kd && (walk != o.kd_walks.front() || kt != o.kd_kts.front())) continue;
                    const SimdVariant v{width, sw, swx, merge, floor, shared, walk, kt};
                    st.built.push_back(accel::make_accel(*kind, tris, simd_config(o, v)));
                    if (const auto* bvh = dynamic_cast<const accel::BvhAccel*>(st.built.back().get())) {
                        const double ntris = double(std::max<std::size_t>(tris.triangle_count(), 1));
                        layouts.push_back({scene, s, tris.triangle_count(), bvh->wide_shape().width, bvh->wide_shape().nodes,
                                           bvh->wide_shape().leaves, double(bvh->wide_shape().memory_bytes) / ntris,
                                           bvh->stats().bytes_per_triangle(), bvh->stats().build_ms});
                    }
                    st.names.push_back(variant_name(o, s, kd, v));
                    st.reference.push_back(false);
                }
    }
    return st;
}

/// The timed configurations of one ray file: each build with each path it offers, then Embree's calls.
std::vector<Config> trace_configs(const Options& o, const Structures& st, [[maybe_unused]] const Peer* peer,
                                  accel::Query q, [[maybe_unused]] bool coherent) {
    std::vector<Config> configs;
    for (std::size_t b = 0; b < st.built.size(); ++b)
        for (const std::string& p : o.paths) {
            const auto path = *accel::parse_trace_path(p);
            // The scalar path (once per structure: it does not depend on the width) on the
            // scalar-only build, every other path on the SIMD-only ones.
            if ((path == accel::TracePath::scalar) != st.reference[b]) continue;
            if (path != accel::TracePath::scalar && path != accel::TracePath::best && !st.built[b]->offer().has(path)) continue;
            const accel::Accel* a = st.built[b].get();
            configs.push_back({st.names[b], p, [a, q, path](auto r, auto h) { accel::trace_parallel(*a, r, h, q, path); }, false, {}, -1});
        }
#ifdef ARBOR_HAVE_EMBREE
    if (peer)
        for (const auto call : perf::embree_calls()) {
            configs.push_back({"embree", std::string(perf::to_string(call)),
                               [peer, q, call, coherent](auto r, auto h) { peer->trace_parallel(r, h, q, call, coherent); }, true, {}, -1});
        }
#endif
    return configs;
}

/// Validates every configuration: against the scalar path of its structure (Embree against the
/// first structure's), against Embree's rtcIntersect1 (arbor's), and against brute force on an
/// evenly spread sample (it costs rays x triangles). Fills err, err_embree and err_brute.
void validate(const Options& o, const Structures& st, [[maybe_unused]] const Peer* peer, const accel::TriangleView& tris,
              std::span<const accel::Ray> rays, accel::Query q, std::vector<Config>& configs) {
    const bool any = q == accel::Query::any;
    std::map<std::string, std::vector<accel::Hit>> scalar;
    std::vector<accel::Hit> hits(rays.size());
    for (std::size_t b = 0; b < st.built.size(); ++b) {
        auto& ref = scalar[st.names[b].substr(0, st.names[b].find('/'))];
        if (!ref.empty()) continue;
        ref.resize(rays.size());
        accel::trace_parallel(*st.built[b], rays, ref, q, accel::TracePath::scalar);
    }
    std::vector<accel::Hit> embree_ref;
#ifdef ARBOR_HAVE_EMBREE
    if (peer) {
        embree_ref.resize(rays.size());
        peer->trace_parallel(rays, embree_ref, q, perf::EmbreeCall::single, false);
    }
#endif
    const accel::BruteAccel brute(tris);
    const std::size_t sample = std::min<std::size_t>(rays.size(), o.brute_sample);
    std::vector<accel::Ray> sample_rays(sample);
    std::vector<accel::Hit> truth(sample);
    for (std::size_t k = 0; k < sample; ++k) sample_rays[k] = rays[k * rays.size() / sample];
    accel::trace_parallel(brute, sample_rays, truth, q, accel::TracePath::scalar, 16);
    for (Config& c : configs) {
        c.trace(rays, hits);
        c.err_brute = 0;
        for (std::size_t k = 0; k < sample; ++k) c.err_brute += !agree(hits[k * rays.size() / sample], truth[k], any);
        const auto& ref = c.embree ? scalar.at(st.names[0].substr(0, st.names[0].find('/')))
                                   : scalar.at(c.structure.substr(0, c.structure.find('/')));
        c.err = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) c.err += !agree(hits[i], ref[i], any);
        if (!c.embree && !embree_ref.empty()) {
            c.err_embree = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) c.err_embree += !agree(hits[i], embree_ref[i], any);
        }
    }
}

/// Times the configurations round-robin, the order rotated each repeat; each sample repeats the
/// pass until o.min_ms have passed and keeps the time per pass.
void time_configs(const Options& o, std::span<const accel::Ray> rays, std::vector<Config>& configs) {
    std::vector<accel::Hit> hits(rays.size());
    for (int rep = 0; rep < o.repeats; ++rep)
        for (std::size_t j = 0; j < configs.size(); ++j) {
            Config& c = configs[(j + std::size_t(rep)) % configs.size()];
            const accel::Timer t;
            const double c0 = cpu_ms();
            int passes = 0;
            do {
                c.trace(rays, hits);
                ++passes;
            } while (t.ms() < o.min_ms);
            c.ms.push_back((o.cpu_time ? (cpu_ms() - c0) / double(o.threads) : t.ms()) / passes);
        }
}

/// The Embree in the comparison, for the report's header (its version names the tables' "Embree").
std::string embree_line([[maybe_unused]] const Options& o) {
#ifdef ARBOR_HAVE_EMBREE
    return o.embree ? perf::embree_description() : "Embree left out (--no-embree)";
#else
    return "no Embree peer in this build";
#endif
}

void run_scene(const Options& o, const std::string& scene, std::vector<perf::PathsRow>& rows, std::vector<LayoutRow>& layouts) {
    engine::Warnings w;
    // builtin:NAME scenes are made here (their files are named with '-' for ':').
    const engine::Mesh mesh = engine::is_builtin_scene(scene) ? engine::make_builtin_scene(scene).mesh
                                                              : engine::load_obj(o.models + "/" + scene + ".obj", w);
    std::string file_stem = scene;
    std::replace(file_stem.begin(), file_stem.end(), ':', '-');
    const accel::TriangleView tris = mesh.view();
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(o.threads));

    const Structures st = build_structures(o, scene, tris, layouts);
    std::unique_ptr<Peer> peer;
#ifdef ARBOR_HAVE_EMBREE
    if (o.embree) peer = std::make_unique<perf::EmbreePeer>(tris);
#endif

    const std::vector<std::string> views = o.views.empty() ? std::vector<std::string>{""} : o.views;
    for (const std::string& view : views)
    for (const std::string& kind : o.kinds) {
        const std::string file = o.rays_dir + "/" + file_stem + (view.empty() ? "" : "-" + view) + "-" + kind + ".rays";
        const std::string cell = view.empty() ? scene : scene + "/" + view;
        const std::vector<accel::Ray> rays = engine::read_rays(file);
        // Kinds named shadow* (shadow-area, shadow-near, ...: scripts/bench_heldout.sh) are any-hit.
        const bool any = kind.rfind("shadow", 0) == 0, coherent = kind == "primary" || any;
        const accel::Query q = any ? accel::Query::any : accel::Query::closest;
        std::vector<Config> configs = trace_configs(o, st, peer.get(), q, coherent);
        validate(o, st, peer.get(), tris, rays, q, configs);
        time_configs(o, rays, configs);
        for (const Config& c : configs) {
            const double mr = double(rays.size()) * 1e-3;
            const auto [lo, hi] = std::minmax_element(c.ms.begin(), c.ms.end());
            rows.push_back({cell, kind, c.structure, c.path, mr / median(c.ms), mr / *hi, mr / *lo, c.err, c.err_brute,
                            c.err_embree, rays.size(), c.embree});
            std::fprintf(stderr, "%-20s %-8s %-16s %-7s %7.2f Mrays/s [%5.2f-%5.2f] err %lld brute %lld/%zu\n", cell.c_str(),
                         kind.c_str(), c.structure.c_str(), c.path.c_str(), rows.back().mrays, rows.back().lo, rows.back().hi, c.err,
                         c.err_brute, std::min(o.brute_sample, rays.size()));
        }
    }
}

std::string fmt(const char* f, double a, double b = 0, double c = 0) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, a, b, c);
    return buf;
}

/// The first three fields of /proc/loadavg.
std::string load_average() {
    std::ifstream f("/proc/loadavg");
    std::string a, b, c;
    f >> a >> b >> c;
    return a + " " + b + " " + c;
}

}  // namespace

static int paths_main(int argc, char** argv) {
    CLI::App app{"arbor-bench paths: arbor's paths and widths against Embree on the same .rays files"};
    Options o;
    app.add_option("--rays", o.rays_dir, "folder of <scene>-<kind>.rays files")->required();
    app.add_option("--models", o.models, "folder of .obj models")->capture_default_str();
    app.add_option("--scenes", o.scenes, "model names")->delimiter(',');
    app.add_option("--kinds", o.kinds, "ray kinds")->delimiter(',');
    app.add_option("--views", o.views, "views per scene: files <scene>-<view>-<kind>.rays (held-out sets)")->delimiter(',');
    app.add_option("--structures", o.structures, "structures")->delimiter(',');
    app.add_option("--paths", o.paths, "arbor paths: scalar, single, packet, best")->delimiter(',');
    app.add_option("--widths", o.widths, "BVH widths (0 = default)")->delimiter(',');
    app.add_option("--threads", o.threads, "threads")->check(CLI::Range(1, 4096));
    app.add_option("--repeats", o.repeats, "timed repeats")->check(CLI::Range(1, 1000));
    app.add_option("--switches", o.switches, "values of BuildConfig::packets.switch_lanes (-1 = default)")->delimiter(',');
    app.add_option("--switches-mixed", o.switches_mixed, "values of BuildConfig::packets.switch_mixed (-1 = default)")
        ->delimiter(',');
    app.add_option("--kd-walks", o.kd_walks, "kd-tree SIMD walks: ropes, cells, tight (cells cut to their triangles' bounds), default")->delimiter(',');
    app.add_option("--kd-kts", o.kd_kts, "kd-tree SAH traversal costs K_T of the SIMD builds (0 = default)")->delimiter(',');
    app.add_option("--packet-lanes", o.packet_lanes, "BuildConfig::packets.lanes (8 or 16; 0 = default)");
    app.add_option("--merges", o.merges, "values of BuildConfig::wide.merge_triangles (0 = the width)")->delimiter(',');
    app.add_option("--floors", o.floors, "values of BuildConfig::bvh.simd_leaf_floor (0 = the width, 1 = the fine tree)")->delimiter(',');
    app.add_option("--shared-leaves", o.shared, "values of BuildConfig::wide.shared_leaf_triangles (0 = no shared root leaves)")->delimiter(',');
    app.add_flag("!--no-embree", o.embree, "leave Embree out");
    app.add_option("--brute-sample", o.brute_sample, "rays per file checked against brute")->capture_default_str();
    app.add_flag("--cpu-time", o.cpu_time, "time by process CPU time / threads, not the wall clock (for a loaded machine)");
    app.add_option("--min-ms", o.min_ms, "repeat the pass within one timed sample until this many ms have passed")
        ->check(CLI::Range(0.0, 60000.0));
    app.add_option("-o,--out", o.out, "also write the Markdown table here");
    try {
        app.parse(argc, argv);
        for (const std::string& p : o.paths)
            if (!accel::parse_trace_path(p)) throw engine::InputError("--paths: unknown path '" + p + "'");
        std::string cmd = "arbor-bench paths";
        for (int i = 1; i < argc; ++i) cmd += std::string(" ") + argv[i];
        const std::string load_before = load_average();
        const accel::Timer total;
        std::vector<perf::PathsRow> rows;
        std::vector<LayoutRow> layouts;
        for (const std::string& scene : o.scenes) run_scene(o, scene, rows, layouts);
        std::ostringstream head;
        head << "- command: `" << cmd << "`\n- "
             << std::to_string(o.threads) +
                    (o.cpu_time ? " threads, process CPU time / threads" : " threads, wall clock")
             << ", median of " << o.repeats << " repeats"
             << (o.min_ms > 0 ? " (each the time per pass of as many passes as fill " + fmt("%.0f", o.min_ms) + " ms)"
                              : std::string())
             << ", all configurations round-robin (order rotated each repeat)\n"
             << "- peer: " << embree_line(o) << "\n"
             << "- load average " << load_before << " at the start, " << load_average() << " at the end; "
             << fmt("%.0f s", total.seconds()) << "\n\n";
        std::ostringstream lay;
        lay << "\n## SIMD layouts\n\n| scene | triangles | structure | width | nodes | leaves | wide layout B/tri | all B/tri | build ms |\n"
               "|---|---:|---|---:|---:|---:|---:|---:|---:|\n";
        for (const LayoutRow& l : layouts)
            lay << "| " << l.scene << " | " << l.triangles << " | " << l.structure << " | " << l.width << " | " << l.nodes << " | "
                << l.leaves << " | " << fmt("%.1f", l.wide_bytes_per_tri) << " | " << fmt("%.1f", l.all_bytes_per_tri) << " | "
                << fmt("%.1f", l.build_ms) << " |\n";
        const std::string table = head.str() + perf::paths_report(rows, o.brute_sample) + (o.views.empty() ? std::string() : "\n" + perf::paths_distribution(rows, o.brute_sample)) + lay.str();
        std::fputs(table.c_str(), stdout);
        if (!o.out.empty()) std::ofstream(o.out) << table;
        return 0;
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "arbor-bench paths: %s\n", e.what());
        return 1;
    }
}

int arbor::perf::paths_command(int argc, char** argv) { return paths_main(argc, argv); }
