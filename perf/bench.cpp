/// `arbor_bench`: the benchmark matrix (perf/README.md). Validates every configuration first,
/// then times it, and writes bench.json, bench.csv and bench.md into --out.
#include "engine/error.h"
#include "perf/bench_plan.h"
#include "perf/bench_report.h"
#include "perf/bench_run.h"

#ifdef ARBOR_HAVE_EMBREE
#include "perf/embree_peer.h"
#endif

#include <CLI/CLI.hpp>
#include <oneapi/tbb/version.h>
#include <xsimd/xsimd.hpp>

#include <cstdio>
#include <ctime>
#include <new>

namespace {

std::string now_iso() {
    const std::time_t t = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S", std::localtime(&t));
    return buf;
}

std::string libraries() {
    std::string s = "oneTBB " TBB_VERSION_STRING ", xsimd " + std::to_string(XSIMD_VERSION_MAJOR) + "." +
                    std::to_string(XSIMD_VERSION_MINOR) + "." + std::to_string(XSIMD_VERSION_PATCH);
#ifdef __AVX512F__
    s += ", ISA AVX-512";
#elif defined(__AVX2__)
    s += ", ISA AVX2";
#endif
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    using arbor::perf::BenchOptions;
    CLI::App app{"arbor_bench: every structure on every scene and ray kind, validated then timed, beside Embree"};
    bool quick = false;
    std::string out = "bench-out";
    std::string models = std::string(ARBOR_SHARED_SCENES) + "/models";
    std::vector<std::string> scenes, kinds, structures;
    std::vector<int> threads;
    std::vector<double> budgets;
    std::size_t rays = 0;
    int repeats = 0, build_repeats = 0, scaling_max = 0;
    bool no_embree = false, no_variants = false, time_brute = false, quiet = false;
    std::uint64_t seed = 1;
    app.add_flag("--quick", quick, "the two-minute variant (small scenes, fewer rays and repeats)");
    app.add_option("-o,--out", out, "output folder for bench.json, bench.csv, bench.md")->capture_default_str();
    app.add_option("--models", models, "folder of .obj models")->capture_default_str();
    app.add_option("--scenes", scenes, "scenes: all, models, stadium, interior, grass, soup, scaling, tiny, "
                                       "replicated-1e3..7, or model names")->delimiter(',');
    app.add_option("--kinds", kinds, "ray kinds: primary, shadow, diffuse, random")->delimiter(',');
    app.add_option("--structures", structures, "structures: bvh-median, bvh-sah, lbvh, kdtree")->delimiter(',');
    app.add_option("--threads", threads, "thread counts, 0 = all (default 1,0)")->delimiter(',')->check(CLI::Range(0, 4096));
    app.add_option("--budgets", budgets, "ray budgets for build + trace totals")->delimiter(',')->check(CLI::PositiveNumber);
    app.add_option("--rays", rays, "rays per scene and kind")->check(CLI::Range(std::size_t(16), std::size_t(1) << 26));
    app.add_option("--repeats", repeats, "timed repeats per configuration")->check(CLI::Range(1, 1000));
    app.add_option("--build-repeats", build_repeats, "builds per structure and thread count")->check(CLI::Range(1, 100));
    app.add_option("--scaling-max", scaling_max, "largest replicated scene, 10^N triangles (3..7)")->check(CLI::Range(3, 7));
    app.add_option("--seed", seed, "ray seed")->capture_default_str();
    app.add_flag("--no-embree", no_embree, "leave the Embree peer out");
    app.add_flag("--no-embree-variants", no_variants, "only Embree's default mode (not HIGH, not ROBUST)");
    app.add_flag("--time-brute", time_brute, "also time brute (tiny scenes only)");
    bool no_auto = false;
    app.add_flag("--no-auto", no_auto, "do not evaluate --accel auto (e.g. a run that only feeds perf/model/fit_auto_model.py)");
    app.add_flag("-q,--quiet", quiet, "no progress lines");
    try {
        app.parse(argc, argv);
        BenchOptions o = quick ? BenchOptions::quick() : BenchOptions{};
        o.models_dir = models;
        if (!scenes.empty()) o.scenes = scenes;
        if (!kinds.empty()) o.kinds = kinds;
        if (!structures.empty()) o.structures = structures;
        if (!threads.empty()) o.threads = threads;
        if (!budgets.empty()) o.budgets = budgets;
        if (rays) o.rays = o.scaling_rays = rays;
        if (repeats) o.repeats = repeats;
        if (build_repeats) o.build_repeats = build_repeats;
        if (scaling_max) o.scaling_max_exp = scaling_max;
        o.seed = seed;
        o.embree = !no_embree;
        if (no_variants) o.embree_variants = false;
        o.time_brute = time_brute;
        if (no_auto) o.evaluate_auto = false;
        o.verbose = !quiet;

        arbor::perf::BenchResult r = arbor::perf::run_bench(o);
        r.date = now_iso();
        std::string cmd;
        for (int i = 0; i < argc; ++i) cmd += (i ? " " : "") + std::string(i ? argv[i] : "arbor_bench");
        r.command = cmd;
        r.compiler = "GCC " __VERSION__;
        r.libraries = libraries();
#ifdef ARBOR_HAVE_EMBREE
        r.embree = o.embree ? arbor::perf::embree_description() : "left out (--no-embree)";
#else
        r.embree = "not built (Embree 3 not found or ARBOR_EMBREE=OFF)";
#endif
        arbor::perf::write_reports(r, out);
        std::printf("arbor_bench: %zu rows in %.1f s -> %s/bench.{json,csv,md}\n", r.rows.size(), r.seconds, out.c_str());
        return 0;
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "arbor_bench: %s\n", e.what());
        return 2;
    } catch (const arbor::engine::InputError& e) {
        std::fprintf(stderr, "arbor_bench: %s\n", e.what());
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "arbor_bench: out of memory\n");
        return 3;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "arbor_bench: %s\n", e.what());
        return 4;
    }
}
