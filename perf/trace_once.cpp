// `arbor-bench trace-once`: one .rays file traced once on one thread, by one of arbor's paths or by one of
// Embree's calls, for profilers that count (valgrind --tool=callgrind) rather than time. The work
// to count runs inside trace_once_run(), so that
//
//   valgrind --tool=callgrind --branch-sim=yes --cache-sim=yes --toggle-collect='*trace_once_run*'
//            build/v3/perf/arbor-bench trace-once --scene MODEL.obj --rays FILE.rays --with embree-16
//
// counts instructions, branches, mispredictions and cache misses of the traversal alone (the build
// and the file reading are left out). valgrind cannot decode AVX-512: profile an x86-64-v3 build
// (perf/README.md, "Profiling"), where Embree picks its AVX2 kernels too, so both sides are compared
// at the same SIMD width. Shadow ray files (name containing "shadow") are any-hit queries.
#include "perf/commands.h"
#include "accel/factory/make_accel.h"
#include "accel/interface/accel.h"
#include "accel/interface/trace.h"
#include "engine/error.h"
#include "engine/obj_loader.h"
#include "engine/rayfile.h"

#ifdef ARBOR_HAVE_EMBREE
#include "perf/embree_peer.h"
#endif

#include <CLI/CLI.hpp>

#include <cstdio>
#include <functional>
#include <string>
#include <vector>

using namespace arbor;

namespace {

/// The counted region: not inlined, so that --toggle-collect finds it by name.
__attribute__((noinline)) void trace_once_run(const std::function<void()>& work) { work(); }

}  // namespace

static int trace_once_main(int argc, char** argv) {
    CLI::App app{"arbor-bench trace-once: one ray file, traced once on one thread, for callgrind"};
    std::string scene, rays_path, with = "single", structure = "bvh-sah";
    app.add_option("--scene", scene, ".obj model")->required();
    app.add_option("--rays", rays_path, ".rays file (spec/rayfile.md)")->required();
    app.add_option("--with", with,
                   "arbor path (scalar, single, packet) or embree-1, embree-8, embree-16, embree-1M (Embree 3 only)");
    app.add_option("--structure", structure, "arbor structure (bvh-median, bvh-sah, lbvh, kdtree)");
    bool count = false;
    app.add_flag("--counters", count, "arbor: trace with the scalar path's counting loop and print nodes and triangle tests per ray");
    CLI11_PARSE(app, argc, argv);
    try {
        engine::Warnings warnings;
        const engine::Mesh mesh = engine::load_obj(scene, warnings);
        const std::vector<accel::Ray> rays = engine::read_rays(rays_path);
        const bool any = rays_path.find("shadow") != std::string::npos;
        std::vector<accel::Hit> hits(rays.size());
        if (with.rfind("embree-", 0) == 0) {
#ifdef ARBOR_HAVE_EMBREE
            const std::string call = with.substr(7);
            const perf::EmbreeCall c = call == "1"   ? perf::EmbreeCall::single
                                       : call == "8"  ? perf::EmbreeCall::packet8
                                       : call == "16" ? perf::EmbreeCall::packet16
                                       : call == "1M" ? perf::EmbreeCall::stream
                                                      : throw engine::InputError("--with: unknown Embree call '" + with + "'");
            if (!perf::embree_has(c))
                throw engine::InputError("--with " + with + ": " + perf::embree_description() + " has no such call");
            const perf::EmbreePeer peer(mesh.view());
            trace_once_run([&] { peer.trace(rays, hits, any ? accel::Query::any : accel::Query::closest, c, false); });
#else
            throw engine::InputError("--with " + with + ": this build has no Embree peer");
#endif
        } else {
            const auto kind = accel::parse_accel_kind(structure);
            const auto path = accel::parse_trace_path(with);
            if (!kind || *kind == accel::AccelKind::automatic) throw engine::InputError("--structure: unknown structure '" + structure + "'");
            if (!path) throw engine::InputError("--with: unknown path '" + with + "'");
            accel::BuildConfig cfg;
            cfg.layouts = *path == accel::TracePath::scalar ? accel::Layouts::scalar : accel::Layouts::simd;
            const auto built = accel::make_accel(*kind, mesh.view(), cfg);
            if (count) {
                accel::TraceCounters c;
                accel::TraceRequest req{any ? accel::Query::any : accel::Query::closest};
                req.counters = &c;
                built->trace(rays, hits, req);
                const accel::BuildStats& st = built->stats();
                std::printf("counters: %.3f nodes (interior + leaves entered) and %.3f triangle tests per ray; tree: %zu nodes, "
                            "%zu leaves, max depth %u, mean leaf depth %.2f\n",
                            double(c.nodes_visited) / double(c.rays), double(c.triangles_tested) / double(c.rays),
                            std::size_t(st.nodes), std::size_t(st.leaves), unsigned(st.max_depth), double(st.mean_leaf_depth));
            }
            trace_once_run([&] {
                if (any) built->trace(rays, hits, {accel::Query::any, *path});
                else built->trace(rays, hits, {accel::Query::closest, *path});
            });
        }
        std::size_t hit = 0;
        for (const accel::Hit& h : hits) hit += h.is_hit();
        std::printf("%s: %zu rays, %zu hits (%s)\n", with.c_str(), rays.size(), hit, any ? "any hit" : "closest hit");
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "arbor-bench trace-once: %s\n", e.what());
        return 1;
    }
}

int arbor::perf::trace_once_command(int argc, char** argv) { return trace_once_main(argc, argv); }
