#include "perf/bench_cli.h"

#include "perf/bench_report.h"

#ifdef ARBOR_HAVE_EMBREE
#include "perf/embree_peer.h"
#endif

#include <oneapi/tbb/version.h>
#include <xsimd/xsimd.hpp>

#include <cstdio>
#include <ctime>

namespace arbor::perf {

struct BenchCommand {
    bool quick = false;
    std::string out = "bench-out";
    std::string models = std::string(ARBOR_SHARED_SCENES) + "/models";
    std::vector<std::string> scenes, kinds, structures;
    std::vector<int> threads;
    std::vector<double> budgets;
    std::size_t rays = 0;
    int repeats = 0, build_repeats = 0, scaling_max = 0;
    bool no_embree = false, no_variants = false, time_brute = false, quiet = false, no_auto = false;
    std::uint64_t seed = 1;
};

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

std::shared_ptr<BenchCommand> add_bench_options(CLI::App& app) {
    auto c = std::make_shared<BenchCommand>();
    app.add_flag("--quick", c->quick, "the two-minute variant (small scenes, fewer rays and repeats)");
    app.add_option("-o,--out", c->out, "output folder for bench.json, bench.csv, bench.md")->capture_default_str();
    app.add_option("--models", c->models, "folder of .obj models")->capture_default_str();
    app.add_option("--scenes", c->scenes, "scenes: all, models, stadium, interior, grass, soup, scaling, tiny, "
                                          "replicated-1e3..7, or model names")->delimiter(',');
    app.add_option("--kinds", c->kinds, "ray kinds: primary, shadow, diffuse, random")->delimiter(',');
    app.add_option("--structures", c->structures, "structures: bvh-median, bvh-sah, lbvh, kdtree")->delimiter(',');
    app.add_option("--threads", c->threads, "thread counts, 0 = all (default 1,0)")->delimiter(',')->check(CLI::Range(0, 4096));
    app.add_option("--budgets", c->budgets, "ray budgets for build + trace totals")->delimiter(',')->check(CLI::PositiveNumber);
    app.add_option("--rays", c->rays, "rays per scene and kind")->check(CLI::Range(std::size_t(16), std::size_t(1) << 26));
    app.add_option("--repeats", c->repeats, "timed repeats per configuration")->check(CLI::Range(1, 1000));
    app.add_option("--build-repeats", c->build_repeats, "builds per structure and thread count")->check(CLI::Range(1, 100));
    app.add_option("--scaling-max", c->scaling_max, "largest replicated scene, 10^N triangles (3..7)")->check(CLI::Range(3, 7));
    app.add_option("--seed", c->seed, "ray seed")->capture_default_str();
    app.add_flag("--no-embree", c->no_embree, "leave the Embree peer out");
    app.add_flag("--no-embree-variants", c->no_variants, "only Embree's default mode (not HIGH, not ROBUST)");
    app.add_flag("--time-brute", c->time_brute, "also time brute (tiny scenes only)");
    app.add_flag("--no-auto", c->no_auto, "do not evaluate --accel auto (e.g. a run that only feeds perf/model/fit_auto_model.py)");
    app.add_flag("-q,--quiet", c->quiet, "no progress lines");
    return c;
}

BenchOptions bench_options(const BenchCommand& c) {
    BenchOptions o = c.quick ? BenchOptions::quick() : BenchOptions{};
    o.models_dir = c.models;
    if (!c.scenes.empty()) o.scenes = c.scenes;
    if (!c.kinds.empty()) o.kinds = c.kinds;
    if (!c.structures.empty()) o.structures = c.structures;
    if (!c.threads.empty()) o.threads = c.threads;
    if (!c.budgets.empty()) o.budgets = c.budgets;
    if (c.rays) o.rays = o.scaling_rays = c.rays;
    if (c.repeats) o.repeats = c.repeats;
    if (c.build_repeats) o.build_repeats = c.build_repeats;
    if (c.scaling_max) o.scaling_max_exp = c.scaling_max;
    o.seed = c.seed;
    o.embree = !c.no_embree;
    if (c.no_variants) o.embree_variants = false;
    o.time_brute = c.time_brute;
    if (c.no_auto) o.evaluate_auto = false;
    o.verbose = !c.quiet;
    return o;
}

int run_bench_command(const BenchCommand& c, const BenchRunContext& ctx) {
    BenchOptions o = bench_options(c);
    o.rank = ctx.rank;
    if (ctx.rank >= 0) o.log_tag = " r" + std::to_string(ctx.rank);
    BenchResult r = run_bench(o, ctx.share);
    if (!ctx.writes) return 0;
    r.date = now_iso();
    r.command = ctx.command;
    r.compiler = "GCC " __VERSION__;
    r.libraries = libraries();
#ifdef ARBOR_HAVE_EMBREE
    r.embree = o.embree ? embree_description() : "left out (--no-embree)";
#else
    r.embree = "not built (Embree 3 not found or ARBOR_EMBREE=OFF)";
#endif
    write_reports(r, c.out);
    std::printf("%s: %zu rows in %.1f s%s -> %s/bench.{json,csv,md}\n", ctx.program.c_str(), r.rows.size(), r.seconds,
                ctx.on_ranks.c_str(), c.out.c_str());
    return 0;
}

}  // namespace arbor::perf
