#include "perf/bench_run.h"

#include "accel/select/job_shape.h"
#include "accel/structures/brute_accel.h"
#include "accel/util/timer.h"
#include "engine/error.h"
#include "engine/ray_gen.h"
#include "perf/bench_auto.h"
#include "perf/bench_build.h"
#include "perf/bench_plan.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <ctime>
#include <iterator>
#include <unistd.h>

namespace arbor::perf {

using accel::Hit;
using accel::Query;
using accel::Ray;

namespace {

class Progress {
public:
    Progress(bool on, std::string tag) : on_(on), tag_(std::move(tag)) {}
    void operator()(const char* fmt, ...) const __attribute__((format(printf, 2, 3))) {
        if (!on_) return;
        std::fprintf(stderr, "[bench%s %6.1fs] ", tag_.c_str(), timer_.seconds());
        va_list args;
        va_start(args, fmt);
        std::vfprintf(stderr, fmt, args);
        va_end(args);
        std::fputc('\n', stderr);
    }

private:
    bool on_;
    std::string tag_;
    accel::Timer timer_;
};

std::string host_name() {
    char name[256] = {};
    return ::gethostname(name, sizeof name - 1) == 0 ? std::string(name) : std::string();
}

/// CPU time of the whole process, ms (all threads).
double process_cpu_ms() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

/// The first three fields of /proc/loadavg ("" elsewhere): other processes skew every timing.
std::string load_average() {
    std::FILE* f = std::fopen("/proc/loadavg", "r");
    if (!f) return {};
    char buf[128] = {};
    const bool ok = std::fgets(buf, sizeof buf, f) != nullptr;
    std::fclose(f);
    if (!ok) return {};
    std::string s(buf);
    std::size_t pos = 0;
    for (int i = 0; i < 3 && pos != std::string::npos; ++i) pos = s.find(' ', pos + 1);
    return s.substr(0, pos);
}

std::vector<int> resolve_threads(const std::vector<int>& requested) {
    const int hw = tbb::info::default_concurrency();
    std::vector<int> out;
    for (int t : requested) {
        t = t <= 0 ? hw : std::min(t, hw);
        if (std::find(out.begin(), out.end(), t) == out.end()) out.push_back(t);
    }
    return out;
}

/// `s` indices spread evenly over [0, n).
std::vector<std::size_t> spread(std::size_t n, std::size_t s) {
    s = std::min(s, n);
    std::vector<std::size_t> idx(s);
    for (std::size_t i = 0; i < s; ++i) idx[i] = i * n / s;
    return idx;
}

/// Closest-hit answers agree by the rayfile.md rule; any-hit answers when both hit or both miss.
bool agree(const Hit& a, const Hit& b, Query q) { return q == Query::any ? a.is_hit() == b.is_hit() : accel::hits_agree(a, b); }

long long count_disagreements(std::span<const Hit> a, std::span<const Hit> b, Query q) {
    long long bad = 0;
    for (std::size_t i = 0; i < a.size(); ++i) bad += !agree(a[i], b[i], q);
    return bad;
}

/// Per structure, from the statistics mode: nodes visited and triangles tested per ray.
struct Counted {
    double nodes_per_ray = nan_value, tris_per_ray = nan_value;
};

struct KindInput {
    const BenchScene* scene;
    engine::RayKind kind;
    Query query;
    bool coherent;
    std::vector<Ray> rays;                                    ///< validated (all of them)
    std::function<std::vector<Ray>(std::size_t)> make_rays;  ///< the same kind and seed, another count
    std::vector<std::pair<std::string, double>> shape;        ///< BenchRow::shape (of `rays`)
    accel::SceneShape scene_shape;                            ///< for the shape of fewer timed rays
};

/// The numbers of BenchRow::shape: the scene's and the rays' shape (accel/select/job_shape.h).
std::vector<std::pair<std::string, double>> shape_values(const accel::SceneShape& s, const accel::RayShape& r) {
    return {{"triangles", double(s.triangles)}, {"overlap", s.overlap},     {"spread", s.spread},
            {"size_tail", s.size_tail},         {"thinness", s.thinness},   {"coherent", r.coherent},
            {"together", r.together},           {"any_hit", r.query == Query::any ? 1.0 : 0.0}};
}

/// Step 1 of a kind: brute force's answers on a sample of the rays (brute force costs rays x
/// triangles, so the sample shrinks as the scene grows).
struct Oracle {
    std::vector<std::size_t> sample;  ///< indices into the validated rays
    std::vector<Hit> truth;           ///< brute force's answer per sample ray
};

Oracle brute_sample(const KindInput& in, const accel::BruteAccel& brute, const BenchOptions& o, std::size_t tris) {
    const std::size_t n = in.rays.size();
    const auto sample_size = std::size_t(std::clamp(o.brute_budget / double(std::max<std::size_t>(tris, 1)),
                                                    double(o.min_sample), double(o.max_sample)));
    Oracle out;
    out.sample = spread(n, sample_size);
    std::vector<Ray> sample_rays;
    for (std::size_t i : out.sample) sample_rays.push_back(in.rays[i]);
    out.truth.resize(sample_rays.size());
    accel::trace_parallel(brute, sample_rays, out.truth, in.query, accel::TracePath::scalar, 16);
    return out;
}

/// Step 2: every configuration once on all rays (all threads): the answers for the error columns,
/// and a first time for planning.
struct FirstPass {
    std::vector<std::vector<Hit>> answers;  ///< per configuration
    std::vector<double> pass_ms;            ///< per configuration
    const std::vector<Hit>* embree_ref = nullptr;                    ///< Embree's default call's answers
    std::map<const Built*, const std::vector<Hit>*> scalar_ref;    ///< each arbor structure's scalar answers
};

FirstPass first_pass(const KindInput& in, const std::vector<TraceConfig>& configs) {
    const std::size_t n = in.rays.size();
    FirstPass p;
    p.answers.assign(configs.size(), std::vector<Hit>(n));
    p.pass_ms.resize(configs.size());
    for (std::size_t c = 0; c < configs.size(); ++c) {
        const accel::Timer timer;
        configs[c].trace(in.rays, p.answers[c], in.query, in.coherent);
        p.pass_ms[c] = timer.ms();
    }
    for (std::size_t c = 0; c < configs.size(); ++c) {
        if (configs[c].built->is_embree() && !p.embree_ref && configs[c].built->name == "embree" && configs[c].path == "1")
            p.embree_ref = &p.answers[c];
        if (!configs[c].built->is_embree() && configs[c].path == "scalar") p.scalar_ref[configs[c].built] = &p.answers[c];
    }
    return p;
}

/// Step 3: the statistics mode on a sample, per arbor structure.
std::map<const Built*, Counted> count_visits(const KindInput& in, const std::vector<Built>& built, const BenchOptions& o) {
    std::map<const Built*, Counted> counted;
    const std::vector<std::size_t> count_idx = spread(in.rays.size(), o.count_sample);
    std::vector<Ray> count_rays;
    for (std::size_t i : count_idx) count_rays.push_back(in.rays[i]);
    std::vector<Hit> count_hits(count_rays.size());
    for (const Built& b : built) {
        if (!b.accel) continue;
        accel::TraceCounters tc;
        if (!b.accel->offer().counts) continue;
        b.accel->trace(count_rays, count_hits, {in.query, accel::TracePath::scalar, {}, {}, &tc});
        if (tc.rays > 0)
            counted[&b] = {double(tc.nodes_visited) / double(tc.rays), double(tc.triangles_tested) / double(tc.rays)};
    }
    return counted;
}

/// The rays that are timed: all validated rays, or, when timing them all would take longer than
/// o.kind_seconds, a smaller set of the same kind and seed (a coarser image), never fewer than
/// o.min_timed_rays.
struct TimedRays {
    std::vector<Ray> fewer;                                    ///< empty: the validated rays are timed
    std::vector<std::pair<std::string, double>> shape;        ///< BenchRow::shape of the timed rays
};

TimedRays choose_timed_rays(const KindInput& in, const std::vector<double>& pass_ms, const BenchOptions& o,
                            const std::vector<int>& threads, AutoEvaluator* autos) {
    const std::size_t n = in.rays.size();
    // The first pass ran on all threads; at t threads a pass takes about all/t times as long.
    // Each timing traces the rays as often as it takes to fill o.min_timed_ms.
    const int all = *std::max_element(threads.begin(), threads.end());
    double projected_ms = 0.0, floor_ms = 0.0;
    for (const int t : threads)
        for (const double p : pass_ms) {
            projected_ms += std::max(p * double(all) / double(t), o.min_timed_ms) * double(o.repeats);
            floor_ms += o.min_timed_ms * double(o.repeats);
        }
    TimedRays out;
    if (projected_ms * 1e-3 > o.kind_seconds && n > o.min_timed_rays && in.make_rays) {
        const double room = std::max(o.kind_seconds * 1e3 - floor_ms, 0.1 * o.kind_seconds * 1e3);
        const auto m = std::max(o.min_timed_rays, std::size_t(double(n) * room / std::max(projected_ms - floor_ms, 1.0)));
        if (m < n) out.fewer = in.make_rays(m);
    }
    // The rows' times are of the timed rays: their shape goes with them (the cost model is fitted
    // on it), and auto is asked about them, not about the finer image's more coherent rays that
    // were validated (it was, and its packets were judged by the coarser image's times).
    out.shape = in.shape;
    if (!out.fewer.empty()) {
        const float diag = simd::length(in.scene_shape.bounds.extent());
        out.shape = shape_values(in.scene_shape, accel::ray_shape(out.fewer, double(out.fewer.size()), in.query, diag));
        if (autos) autos->set_rays(out.fewer);
    }
    return out;
}

/// The path TracePath::best takes, per arbor structure: the majority over the trace chunks.
std::map<const Built*, accel::TracePath> best_paths(const std::vector<Built>& built, std::span<const Ray> timed,
                                                    Query query) {
    const std::size_t nt = timed.size();
    std::map<const Built*, accel::TracePath> best_of;
    for (const Built& b : built) {
        if (!b.accel) continue;
        std::map<accel::TracePath, std::size_t> votes;
        for (std::size_t i = 0; i < nt; i += 1024) {
            const auto chunk = timed.subspan(i, std::min<std::size_t>(1024, nt - i));
            ++votes[accel::choose_path(b.accel->offer(), chunk, {query}).path];
        }
        best_of[&b] = std::max_element(votes.begin(), votes.end(), [](const auto& x, const auto& y) {
                          return x.second < y.second;
                      })->first;
    }
    return best_of;
}

/// Wall and CPU ms per pass over the timed rays, per configuration and repeat, at `t` threads.
struct Timings {
    std::vector<std::vector<double>> ms, cpu;
};

/// Step 4 at one thread count: K repeats, all configurations round-robin, the order rotated each
/// repeat. Each timing traces the rays as often as it takes to fill o.min_timed_ms (a 2 ms trace on
/// a shared machine is one scheduler slice: it runs undisturbed or waits a whole slice).
Timings time_round_robin(const KindInput& in, const std::vector<TraceConfig>& configs, const std::vector<Ray>& timed,
                         const BenchOptions& o, int t, AutoEvaluator* autos) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(t));
    std::vector<Hit> scratch(timed.size());
    Timings out{std::vector<std::vector<double>>(configs.size()), std::vector<std::vector<double>>(configs.size())};
    for (int rep = 0; rep < o.repeats; ++rep) {
        // --accel auto's decisions take one turn of the round-robin, at a place that moves too.
        const std::size_t turns = configs.size() + (autos ? 1 : 0);
        for (std::size_t j = 0; j < turns; ++j) {
            const std::size_t c = (j + std::size_t(rep)) % turns;
            if (c == configs.size()) {
                autos->run(t);
                continue;
            }
            const double cpu0 = process_cpu_ms();
            const accel::Timer timer;
            std::size_t passes = 0;
            double elapsed = 0.0;
            do {
                configs[c].trace(timed, scratch, in.query, in.coherent);
                ++passes;
                elapsed = timer.ms();
            } while (elapsed < o.min_timed_ms);
            out.ms[c].push_back(elapsed / double(passes));  // per pass over the timed rays
            out.cpu[c].push_back((process_cpu_ms() - cpu0) / double(passes) / double(t));
        }
    }
    return out;
}

/// Everything a row needs beyond its configuration's timings.
struct RowContext {
    const KindInput& in;
    const std::string& kind_name;
    std::size_t tris;
    const std::vector<Ray>& timed;
    const TimedRays& timed_rays;
    const Oracle& oracle;
    const FirstPass& first;
    const std::map<const Built*, Counted>& counted;
    const std::map<const Built*, accel::TracePath>& best_of;
    const BenchOptions& o;
};

BenchRow make_row(const RowContext& x, const TraceConfig& cfg, std::size_t c, int t, const Timings& tm) {
    const Built& b = *cfg.built;
    const std::size_t nt = x.timed.size();
    const std::vector<Hit>& answers = x.first.answers[c];
    BenchRow r;
    r.scene = x.in.scene->name;
    r.family = x.in.scene->family;
    r.kind = x.kind_name;
    r.query = x.in.query == Query::any ? "any" : "closest";
    r.structure = b.name;
    r.path = cfg.path;
    r.best_path = b.accel && x.best_of.count(&b) && x.best_of.at(&b) == cfg.arbor_path;
    r.embree = b.is_embree();
    r.threads = t;
    r.triangles = x.tris;
    r.rays = nt;
    r.validated_rays = x.in.rays.size();
    r.shape = x.timed_rays.shape;
    const auto bt = b.build_ms.find(t);
    if (bt != b.build_ms.end()) r.build_ms = summarize(bt->second), r.build_samples = bt->second;
    r.trace_ms = summarize(tm.ms[c]);
    r.trace_samples = tm.ms[c];
    r.trace_cpu_ms = summarize(tm.cpu[c]);
    r.trace_cpu_samples = tm.cpu[c];
    const double mr = double(nt) * 1e-3;  // rays per ms -> Mrays/s
    r.mrays = {mr / r.trace_ms.median, mr / r.trace_ms.max, mr / r.trace_ms.min};
    if (b.accel) {
        const accel::BuildStats& s = b.accel->stats();
        r.nodes = double(s.nodes), r.leaves = double(s.leaves), r.max_depth = double(s.max_depth);
        r.sah_cost = s.sah_cost;
        r.bytes_per_triangle = s.bytes_per_triangle();
        if (const auto it = x.counted.find(&b); it != x.counted.end())
            r.nodes_per_ray = it->second.nodes_per_ray, r.tris_per_ray = it->second.tris_per_ray;
    } else {
        r.bytes_per_triangle = x.tris ? double(b.memory_bytes()) / double(x.tris) : nan_value;
    }
    const std::vector<std::size_t>& sample = x.oracle.sample;
    r.brute_sample = sample.size();
    r.err_brute = 0;
    for (std::size_t k = 0; k < sample.size(); ++k)
        r.err_brute += !agree(answers[sample[k]], x.oracle.truth[k], x.in.query);
    if (const auto it = x.first.scalar_ref.find(&b); it != x.first.scalar_ref.end() && cfg.path != "scalar")
        r.err_scalar = count_disagreements(answers, *it->second, x.in.query);
    if (x.first.embree_ref) r.err_embree = count_disagreements(answers, *x.first.embree_ref, x.in.query);
    for (const double budget : x.o.budgets) {
        r.total_ms.push_back(r.build_ms.median + budget / (r.mrays.median * 1e6) * 1e3);
        r.total_cpu_ms.push_back(r.build_ms.min + budget * r.trace_cpu_ms.median / double(nt));
    }
    return r;
}

/// One ray kind of one scene: validate every configuration against brute force and each other,
/// then time them, one row per configuration and thread count.
void run_kind(const KindInput& in, const std::vector<Built>& built, const std::vector<TraceConfig>& configs,
              const accel::BruteAccel& brute, const BenchOptions& o, const std::vector<int>& threads,
              const Progress& log, AutoEvaluator* autos, BenchResult& out) {
    const std::size_t tris = in.scene->scene.mesh.triangle_count();
    const std::string kind_name(engine::to_string(in.kind));
    const Oracle oracle = brute_sample(in, brute, o, tris);
    const FirstPass first = first_pass(in, configs);
    const std::map<const Built*, Counted> counted = count_visits(in, built, o);
    const TimedRays timed_rays = choose_timed_rays(in, first.pass_ms, o, threads, autos);
    const std::vector<Ray>& timed = timed_rays.fewer.empty() ? in.rays : timed_rays.fewer;
    const std::map<const Built*, accel::TracePath> best_of = best_paths(built, timed, in.query);
    const RowContext context{in, kind_name, tris, timed, timed_rays, oracle, first, counted, best_of, o};
    for (const int t : threads) {
        const Timings tm = time_round_robin(in, configs, timed, o, t, autos);
        for (std::size_t c = 0; c < configs.size(); ++c) out.rows.push_back(make_row(context, configs[c], c, t, tm));
    }
    log("  %s: %zu rays validated (brute sample %zu), %zu timed, %zu configurations", kind_name.c_str(), in.rays.size(),
        oracle.sample.size(), timed.size(), configs.size());
}

/// Ratio of each row's median Mrays/s to the best call of Embree's default mode on the same
/// (scene, kind, threads).
void fill_embree_ratios(std::vector<BenchRow>& rows, std::size_t from) {
    std::map<std::tuple<std::string, std::string, int>, double> best;
    for (std::size_t i = from; i < rows.size(); ++i)
        if (rows[i].structure == "embree") {
            double& b = best[{rows[i].scene, rows[i].kind, rows[i].threads}];
            b = std::max(b, rows[i].mrays.median);
        }
    for (std::size_t i = from; i < rows.size(); ++i) {
        const auto it = best.find({rows[i].scene, rows[i].kind, rows[i].threads});
        if (it != best.end() && it->second > 0) rows[i].ratio_embree = rows[i].mrays.median / it->second;
    }
}

void run_scene(const BenchScene& bs, const BenchOptions& o, const std::vector<int>& threads, const Progress& log,
               BuildHistory& history, BenchResult& out) {
    const accel::TriangleView view = bs.scene.mesh.view();
    const std::size_t tris = view.triangle_count();
    const bool scaling = bs.family == "replicated";
    log("scene %s: %zu triangles", bs.name.c_str(), tris);
    // Big scenes: one build, all threads only, Embree's default mode only.
    const bool big = tris > o.big_scene;
    const int all = *std::max_element(threads.begin(), threads.end());
    const std::vector<int> scene_threads = big ? std::vector<int>{all} : threads;
    BenchOptions so = o;
    if (big) {
        so.embree_variants = false;
        out.notes.push_back(bs.name + ": above " + std::to_string(o.big_scene) +
                            " triangles: one build per structure, " + std::to_string(all) +
                            " threads only, Embree default mode only");
    }
    const int build_repeats = tris > o.single_build_above ? 1 : std::max(o.build_repeats, 1);
    std::vector<Built> built = build_structures(view, so, scene_threads, build_repeats, out.notes, history);
    for (const Built& b : built) {
        const auto& v = b.build_ms.at(all);
        log("  built %s: %.1f ms (median of %zu at %d threads)", b.name.c_str(), summarize(v).median, v.size(), all);
    }
    const std::vector<TraceConfig> configs = trace_configs(built);
    const accel::BruteAccel brute(view);

    // Primary hits for shadow/diffuse rays: the fastest tracer at hand (any correct one gives the
    // same rays up to ties and rounding).
    const TraceConfig* gen = nullptr;
    for (const TraceConfig& c : configs)
        if (!gen || (c.built->is_embree() && !gen->built->is_embree())) gen = &c;
    engine::PrimaryTracer tracer = [&](std::span<const Ray> r, std::span<Hit> h) {
        if (gen) gen->trace(r, h, Query::closest, true);
        else accel::trace_parallel(brute, r, h, Query::closest);
    };
    const engine::RayGenScene gscene = engine::ray_gen_scene(bs.scene, bs.use_scene_camera);

    const accel::SceneShape scene_shape = accel::scene_shape(view);
    const std::size_t first_row = out.rows.size();
    for (const std::string& kname : o.kinds) {
        const engine::RayKind kind = *engine::parse_ray_kind(kname);
        if (scaling && kind != engine::RayKind::primary && kind != engine::RayKind::diffuse) continue;
        engine::RayGenConfig rc;
        rc.kind = kind;
        rc.count = scaling ? o.scaling_rays : o.rays;
        rc.seed = o.seed;
        KindInput in{&bs, kind, kind == engine::RayKind::shadow ? Query::any : Query::closest,
                     kind == engine::RayKind::primary || kind == engine::RayKind::shadow, {}, {}, {}, {}};
        in.make_rays = [&gscene, rc, &tracer](std::size_t count) {
            engine::RayGenConfig c = rc;
            c.count = count;
            return engine::generate_rays(gscene, c, tracer);
        };
        try {
            in.rays = in.make_rays(rc.count);
        } catch (const engine::InputError& e) {
            out.notes.push_back(bs.name + " " + kname + ": " + e.what());
            continue;
        }
        const float diag = simd::length(scene_shape.bounds.extent());
        in.shape = shape_values(scene_shape, accel::ray_shape(in.rays, double(in.rays.size()), in.query, diag));
        in.scene_shape = scene_shape;
        const std::size_t kind_from = out.rows.size();
        // --accel auto on these rays for each budget, decided afresh in every repeat (bench_auto.h),
        // with the build settings of the timed structures (so a structure its probe built is theirs).
        // Not where no fixed configuration is timed (every build skipped as too slow): nothing to
        // judge auto against, and each decision on such a scene may build whole structures.
        std::optional<AutoEvaluator> autos;
        if (o.evaluate_auto && !configs.empty()) autos.emplace(view, in.rays, in.query, accel::BuildConfig{}, o.budgets);
        run_kind(in, built, configs, brute, o, scene_threads, log, autos ? &*autos : nullptr, out);
        if (autos) autos->judge(in.scene->name, std::string(engine::to_string(kind)), kind_from, out);
    }
    fill_embree_ratios(out.rows, first_row);
}

}  // namespace

Stat3 summarize(std::vector<double> v) {
    if (v.empty()) return {};
    std::sort(v.begin(), v.end());
    const std::size_t m = v.size() / 2;
    const double median = v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
    return {median, v.front(), v.back()};
}

BenchResult run_bench(const BenchOptions& o, const SceneShare& share) {
    for (const std::string& k : o.kinds)
        if (!engine::parse_ray_kind(k))
            throw engine::InputError("--kinds: unknown ray kind '" + k + "' (expected primary, shadow, diffuse, random)");
    (void)bench_structures(o);  // validates the names
    const std::vector<SceneSource> plan = plan_scenes(o);
    const std::vector<int> threads = resolve_threads(o.threads);
    const Progress log(o.verbose, o.log_tag);
    const accel::Timer timer;
    BenchResult out;
    out.load_before = load_average();
    out.budgets = o.budgets;
    out.hardware_threads = tbb::info::default_concurrency();
    // The build history predicts build times from this process's earlier scenes (to skip builds
    // over max_build_seconds); spread over processes, each has its own.
    BuildHistory history;
    const std::string host = host_name();
    auto run_one = [&](std::size_t i) {
        BenchResult part;
        try {
            const BenchScene scene = plan[i].make();
            run_scene(scene, o, threads, log, history, part);
        } catch (const std::bad_alloc&) {
            part.notes.push_back(plan[i].name + ": out of memory, skipped");
        }
        for (BenchRow& r : part.rows) r.host = host, r.rank = o.rank;
        return part;
    };
    std::vector<BenchResult> parts;
    if (share) {
        parts = share(plan.size(), run_one);
    } else {
        for (std::size_t i = 0; i < plan.size(); ++i) parts.push_back(run_one(i));
    }
    for (BenchResult& p : parts) {
        std::move(p.rows.begin(), p.rows.end(), std::back_inserter(out.rows));
        std::move(p.autos.begin(), p.autos.end(), std::back_inserter(out.autos));
        std::move(p.notes.begin(), p.notes.end(), std::back_inserter(out.notes));
    }
    std::sort(out.notes.begin(), out.notes.end());
    out.notes.erase(std::unique(out.notes.begin(), out.notes.end()), out.notes.end());
    out.seconds = timer.seconds();
    out.load_after = load_average();
    return out;
}

}  // namespace arbor::perf
