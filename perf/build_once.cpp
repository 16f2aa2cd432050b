// `arbor-bench build-once`: one build in a fresh process, as a user meets it (cold allocator, page tables and
// thread pool), by Embree (its default MEDIUM build, rtcCommitScene) or by an arbor structure
// (make_accel with the SIMD layouts only, as `arbor trace` builds for its default path). Prints
// one JSON object: build_ms (wall time of the build alone), cpu_ms and minor page faults during it
// (Embree: with its device and buffer setup, setup_ms), and for arbor the SAH cost. scripts/bench_fresh_build.sh runs it interleaved with
// `arbor trace` in fresh processes.
//
//   arbor-bench build-once --scene MODEL.obj|builtin:NAME --with embree|bvh-sah|lbvh|... [--threads 2]
#include "perf/commands.h"
#include "accel/factory/make_accel.h"
#include "accel/interface/accel.h"
#include "accel/util/timer.h"
#include "engine/builtin_scenes.h"
#include "engine/error.h"
#include "engine/obj_loader.h"

#ifdef ARBOR_HAVE_EMBREE
#include "perf/embree_peer.h"
#endif

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <cstdio>
#include <iostream>
#include <string>

using namespace arbor;

namespace {

long minor_faults() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_minflt;
}

/// User + system CPU time of the process so far, ms (a loaded machine stretches the wall time of
/// a 2-thread build, not its CPU time).
double cpu_ms(bool system_only = false) {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    const double sys = double(u.ru_stime.tv_sec) * 1e3 + double(u.ru_stime.tv_usec) * 1e-3;
    return system_only ? sys : sys + double(u.ru_utime.tv_sec) * 1e3 + double(u.ru_utime.tv_usec) * 1e-3;
}

}  // namespace

static int build_once_main(int argc, char** argv) {
    CLI::App app{"arbor-bench build-once: one build in a fresh process (Embree or an arbor structure)"};
    std::string scene, with = "embree";
    int threads = 2;
    app.add_option("--scene", scene, ".obj model or builtin:NAME")->required();
    app.add_option("--with", with, "embree or an arbor structure");
    app.add_option("--threads", threads, "threads")->check(CLI::Range(1, 4096));
    CLI11_PARSE(app, argc, argv);
    try {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        engine::Warnings warnings;
        const engine::Mesh mesh = engine::is_builtin_scene(scene) ? engine::make_builtin_scene(scene).mesh
                                                                  : engine::load_obj(scene, warnings);
        nlohmann::json j;
        j["scene"] = scene;
        j["with"] = with;
        j["triangles"] = mesh.triangle_count();
        j["threads"] = threads;
        const long f0 = minor_faults();
        const double c0 = cpu_ms(), s0 = cpu_ms(true);
        if (with == "embree") {
#ifdef ARBOR_HAVE_EMBREE
            const perf::EmbreePeer peer(mesh.view());
            j["build_ms"] = peer.build_ms();
            j["setup_ms"] = peer.setup_ms();
            j["bytes"] = peer.memory_bytes();
#else
            throw engine::InputError("--with embree: this build has no Embree peer");
#endif
        } else {
            const auto kind = accel::parse_accel_kind(with);
            if (!kind || *kind == accel::AccelKind::automatic) throw engine::InputError("--with: unknown structure '" + with + "'");
            accel::BuildConfig cfg;
            cfg.layouts = accel::Layouts::simd;
            const accel::Timer t;
            const auto built = accel::make_accel(*kind, mesh.view(), cfg);
            j["build_ms"] = t.ms();
            j["sah_cost"] = built->stats().sah_cost;
            j["bytes"] = built->stats().memory_bytes;
        }
        j["minor_faults"] = minor_faults() - f0;
        j["cpu_ms"] = cpu_ms() - c0;  // Embree: its device and buffer setup included
        j["sys_ms"] = cpu_ms(true) - s0;  // the kernel's part: page faults, zeroing pages
        std::cout << j.dump() << '\n';
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "arbor-bench build-once: %s\n", e.what());
        return 1;
    }
}

int arbor::perf::build_once_command(int argc, char** argv) { return build_once_main(argc, argv); }
