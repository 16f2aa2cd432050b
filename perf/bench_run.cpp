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

void run_kind(const KindInput& in, const std::vector<Built>& built, const std::vector<TraceConfig>& configs,
              const accel::BruteAccel& brute, const BenchOptions& o, const std::vector<int>& threads,
              const Progress& log, AutoEvaluator* autos, BenchResult& out) {
    const std::vector<Ray>& rays = in.rays;
    const std::size_t n = rays.size(), tris = in.scene->scene.mesh.triangle_count();
    const std::string kind_name(engine::to_string(in.kind));

    // 1. The oracle on a sample: brute force costs rays x triangles.
    const auto sample_size = std::size_t(std::clamp(o.brute_budget / double(std::max<std::size_t>(tris, 1)),
                                                    double(o.min_sample), double(o.max_sample)));
    const std::vector<std::size_t> sample = spread(n, sample_size);
    std::vector<Ray> sample_rays;
    for (std::size_t i : sample) sample_rays.push_back(rays[i]);
    std::vector<Hit> truth(sample_rays.size());
    accel::trace_parallel(brute, sample_rays, truth, in.query, accel::TracePath::scalar, 16);

    // 2. Every configuration once on all rays (all threads): the answers for the error columns,
    // and a first time for planning.
    std::vector<std::vector<Hit>> answers(configs.size(), std::vector<Hit>(n));
    std::vector<double> pass_ms(configs.size());
    for (std::size_t c = 0; c < configs.size(); ++c) {
        const accel::Timer timer;
        configs[c].trace(rays, answers[c], in.query, in.coherent);
        pass_ms[c] = timer.ms();
    }
    const std::vector<Hit>* embree_ref = nullptr;
    std::map<const Built*, const std::vector<Hit>*> scalar_ref;
    for (std::size_t c = 0; c < configs.size(); ++c) {
        if (configs[c].built->is_embree() && !embree_ref && configs[c].built->name == "embree" && configs[c].path == "1")
            embree_ref = &answers[c];
        if (!configs[c].built->is_embree() && configs[c].path == "scalar") scalar_ref[configs[c].built] = &answers[c];
    }

    // 3. The statistics mode on a sample, per arbor structure.
    std::map<const Built*, Counted> counted;
    const std::vector<std::size_t> count_idx = spread(n, o.count_sample);
    std::vector<Ray> count_rays;
    for (std::size_t i : count_idx) count_rays.push_back(rays[i]);
    std::vector<Hit> count_hits(count_rays.size());
    for (const Built& b : built) {
        if (!b.accel) continue;
        accel::TraceCounters tc;
        if (!b.accel->offer().counts) continue;
        b.accel->trace(count_rays, count_hits, {in.query, accel::TracePath::scalar, {}, {}, &tc});
        if (tc.rays > 0)
            counted[&b] = {double(tc.nodes_visited) / double(tc.rays), double(tc.triangles_tested) / double(tc.rays)};
    }

    // 4. Timing: K repeats at each thread count, all configurations round-robin, the order
    // rotated each repeat. When that would take longer than o.kind_seconds, the timed rays are a
    // smaller set of the same kind and seed (a coarser image), never fewer than o.min_timed_rays.
    // The first pass ran on all threads; at t threads a pass takes about all/t times as long.
    // Each timing traces the rays as often as it takes to fill o.min_timed_ms (a 2 ms trace on a
    // shared machine is one scheduler slice: it runs undisturbed or waits a whole slice).
    const int all = *std::max_element(threads.begin(), threads.end());
    double projected_ms = 0.0, floor_ms = 0.0;
    for (const int t : threads)
        for (const double p : pass_ms) {
            projected_ms += std::max(p * double(all) / double(t), o.min_timed_ms) * double(o.repeats);
            floor_ms += o.min_timed_ms * double(o.repeats);
        }
    std::vector<Ray> fewer;
    if (projected_ms * 1e-3 > o.kind_seconds && n > o.min_timed_rays && in.make_rays) {
        const double room = std::max(o.kind_seconds * 1e3 - floor_ms, 0.1 * o.kind_seconds * 1e3);
        const auto m = std::max(o.min_timed_rays, std::size_t(double(n) * room / std::max(projected_ms - floor_ms, 1.0)));
        if (m < n) fewer = in.make_rays(m);
    }
    const std::vector<Ray>& timed = fewer.empty() ? rays : fewer;
    const std::size_t nt = timed.size();
    // The rows' times are of the timed rays: their shape goes with them (the cost model is fitted
    // on it), and auto is asked about them, not about the finer image's more coherent rays that
    // were validated (it was, and its packets were judged by the coarser image's times).
    std::vector<std::pair<std::string, double>> timed_shape = in.shape;
    if (!fewer.empty()) {
        const float diag = simd::length(in.scene_shape.bounds.extent());
        timed_shape = shape_values(in.scene_shape, accel::ray_shape(fewer, double(nt), in.query, diag));
        if (autos) autos->set_rays(fewer);
    }
    std::vector<Hit> scratch(nt);
    // The path TracePath::best takes, per arbor structure: the majority over the trace chunks.
    std::map<const Built*, accel::TracePath> best_of;
    for (const Built& b : built) {
        if (!b.accel) continue;
        std::map<accel::TracePath, std::size_t> votes;
        for (std::size_t i = 0; i < nt; i += 1024) {
            const auto chunk = std::span<const Ray>(timed).subspan(i, std::min<std::size_t>(1024, nt - i));
            ++votes[accel::choose_path(b.accel->offer(), chunk, {in.query}).path];
        }
        best_of[&b] = std::max_element(votes.begin(), votes.end(), [](const auto& x, const auto& y) {
                          return x.second < y.second;
                      })->first;
    }
    for (const int t : threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(t));
        std::vector<std::vector<double>> ms(configs.size()), cpu(configs.size());
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
                ms[c].push_back(elapsed / double(passes));  // per pass over the timed rays
                cpu[c].push_back((process_cpu_ms() - cpu0) / double(passes) / double(t));
            }
        }
        for (std::size_t c = 0; c < configs.size(); ++c) {
            const TraceConfig& cfg = configs[c];
            const Built& b = *cfg.built;
            BenchRow r;
            r.scene = in.scene->name;
            r.family = in.scene->family;
            r.kind = kind_name;
            r.query = in.query == Query::any ? "any" : "closest";
            r.structure = b.name;
            r.path = cfg.path;
            r.best_path = b.accel && best_of.count(&b) && best_of.at(&b) == cfg.arbor_path;
            r.embree = b.is_embree();
            r.threads = t;
            r.triangles = tris;
            r.rays = nt;
            r.validated_rays = n;
            r.shape = timed_shape;
            const auto bt = b.build_ms.find(t);
            if (bt != b.build_ms.end()) r.build_ms = summarize(bt->second), r.build_samples = bt->second;
            r.trace_ms = summarize(ms[c]);
            r.trace_samples = ms[c];
            r.trace_cpu_ms = summarize(cpu[c]);
            r.trace_cpu_samples = cpu[c];
            const double mr = double(nt) * 1e-3;  // rays per ms -> Mrays/s
            r.mrays = {mr / r.trace_ms.median, mr / r.trace_ms.max, mr / r.trace_ms.min};
            if (b.accel) {
                const accel::BuildStats& s = b.accel->stats();
                r.nodes = double(s.nodes), r.leaves = double(s.leaves), r.max_depth = double(s.max_depth);
                r.sah_cost = s.sah_cost;
                r.bytes_per_triangle = s.bytes_per_triangle();
                if (const auto it = counted.find(&b); it != counted.end())
                    r.nodes_per_ray = it->second.nodes_per_ray, r.tris_per_ray = it->second.tris_per_ray;
            } else {
                r.bytes_per_triangle = tris ? double(b.memory_bytes()) / double(tris) : nan_value;
            }
            r.brute_sample = sample.size();
            r.err_brute = 0;
            for (std::size_t k = 0; k < sample.size(); ++k) r.err_brute += !agree(answers[c][sample[k]], truth[k], in.query);
            if (const auto it = scalar_ref.find(&b); it != scalar_ref.end() && cfg.path != "scalar")
                r.err_scalar = count_disagreements(answers[c], *it->second, in.query);
            if (embree_ref) r.err_embree = count_disagreements(answers[c], *embree_ref, in.query);
            for (const double budget : o.budgets) {
                r.total_ms.push_back(r.build_ms.median + budget / (r.mrays.median * 1e6) * 1e3);
                r.total_cpu_ms.push_back(r.build_ms.min + budget * r.trace_cpu_ms.median / double(nt));
            }
            out.rows.push_back(std::move(r));
        }
    }
    log("  %s: %zu rays validated (brute sample %zu), %zu timed, %zu configurations", kind_name.c_str(), n,
        sample.size(), nt, configs.size());
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
