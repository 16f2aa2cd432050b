#include "perf/bench_auto.h"

#include "accel/select/auto_probe.h"
#include "accel/util/timer.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace arbor::perf {

namespace {

/// The regret of an oracle that picks the (structure, path) with the smallest total on the
/// even-numbered repeats, judged by the odd-numbered ones. NaN with fewer than 2 repeats.
double split_half_regret(const std::vector<BenchRow>& rows, std::size_t from, int threads, double budget, bool cpu) {
    double pick_even = 0.0, pick_odd = 0.0, best_odd = 0.0;
    bool any = false;
    for (std::size_t i = from; i < rows.size(); ++i) {
        const BenchRow& r = rows[i];
        const std::vector<double>& samples = cpu ? r.trace_cpu_samples : r.trace_samples;
        if (r.embree || r.threads != threads || samples.size() < 2) continue;
        std::vector<double> even, odd;
        for (std::size_t k = 0; k < samples.size(); ++k) (k % 2 ? odd : even).push_back(samples[k]);
        auto total = [&](const std::vector<double>& v) {
            return (cpu ? r.build_ms.min : r.build_ms.median) + budget * summarize(v).median / double(r.rays);
        };
        const double e = total(even), o = total(odd);
        if (!any || e < pick_even) pick_even = e, pick_odd = o;
        if (!any || o < best_odd) best_odd = o;
        any = true;
    }
    return any ? pick_odd / best_odd - 1.0 : nan_value;
}

}  // namespace

bool same_twice_within(const BenchRow& row, double budget, bool cpu) {
    const std::vector<double>& samples = cpu ? row.trace_cpu_samples : row.trace_samples;
    if (samples.size() < 2) return false;
    std::vector<double> even, odd;
    for (std::size_t k = 0; k < samples.size(); ++k) (k % 2 ? odd : even).push_back(samples[k]);
    const double build = cpu ? row.build_ms.min : row.build_ms.median;
    const double a = build + budget * summarize(even).median / double(row.rays);
    const double b = build + budget * summarize(odd).median / double(row.rays);
    return std::max(a, b) <= 1.10 * std::min(a, b);
}

AutoEvaluator::AutoEvaluator(const accel::TriangleView& tris, std::span<const accel::Ray> rays, accel::Query query,
                             const accel::BuildConfig& build, std::vector<double> budgets)
    : tris_(tris), rays_(rays), query_(query), build_(build), budgets_(std::move(budgets)) {}

void AutoEvaluator::run(int threads) {
    for (std::size_t b = 0; b < budgets_.size(); ++b) {
        // As `arbor trace --accel auto` asks it: these rays, `budget` of them, the path free.
        const double cpu0 = accel::process_cpu_ms();
        const accel::Timer timer;
        accel::AccelPick pick =
            accel::pick_accel(accel::AccelKind::automatic, accel::trace_job(tris_, rays_, budgets_[b], query_, accel::TracePath::best, build_));
        Trial t;
        t.ms = timer.ms();
        t.cpu_ms = (accel::process_cpu_ms() - cpu0) / double(std::max(threads, 1));
        t.structure = std::string(accel::to_string(pick.kind));
        t.path = std::string(accel::to_string(pick.path));
        t.built = pick.built != nullptr;
        t.probed = pick.probed;
        t.reason = pick.reason;
        trials_[{threads, b}].push_back(std::move(t));
    }
}

void AutoEvaluator::judge(const std::string& scene, const std::string& kind, std::size_t from, BenchResult& out) const {
    for (const auto& [key, trials] : trials_) {
        const auto [threads, bi] = key;
        const double budget = budgets_[bi];
        // The fixed choices: every arbor (structure, path) row at this thread count.
        const BenchRow* best = nullptr;
        const BenchRow* best_cpu = nullptr;
        const BenchRow* fallback = nullptr;  // bvh-sah on the path best takes: the default
        auto total = [&](const BenchRow& r) { return r.build_ms.median + budget * r.trace_ms.median / double(r.rays); };
        auto total_cpu = [&](const BenchRow& r) { return r.build_ms.min + budget * r.trace_cpu_ms.median / double(r.rays); };
        std::map<std::pair<std::string, std::string>, const BenchRow*> by_config;
        for (std::size_t i = from; i < out.rows.size(); ++i) {
            const BenchRow& r = out.rows[i];
            if (r.embree || r.threads != threads) continue;
            by_config[{r.structure, r.path}] = &r;
            if (!best || total(r) < total(*best)) best = &r;
            if (!best_cpu || total_cpu(r) < total_cpu(*best_cpu)) best_cpu = &r;
            if (r.structure == "bvh-sah" && r.best_path) fallback = &r;
        }
        if (!best || trials.empty()) continue;
        // Each trial's job: its own time, its pick's build unless handed over, the budget's trace.
        struct Job {
            double wall, wall_pick, cpu;
            const Trial* trial;
        };
        std::vector<Job> jobs;
        for (const Trial& t : trials) {
            // `best` as the pick's path: the row the path policy would run (the majority path).
            const BenchRow* row = nullptr;
            for (const auto& [config, r] : by_config)
                if (config.first == t.structure && (config.second == t.path || (t.path == "best" && r->best_path))) row = r;
            if (!row) {
                jobs.push_back({nan_value, nan_value, nan_value, &t});
                continue;
            }
            const double trace = budget * row->trace_ms.median / double(row->rays);
            const double trace_cpu = budget * row->trace_cpu_ms.median / double(row->rays);
            const double pick = (t.built ? 0.0 : row->build_ms.median) + trace;
            jobs.push_back({t.ms + pick, row->build_ms.median + trace,
                            t.cpu_ms + (t.built ? 0.0 : row->build_ms.min) + trace_cpu, &t});
        }
        std::sort(jobs.begin(), jobs.end(), [](const Job& a, const Job& b) {
            return (std::isnan(a.wall) ? 1e300 : a.wall) < (std::isnan(b.wall) ? 1e300 : b.wall);
        });
        const Job& mid = jobs[(jobs.size() - 1) / 2];
        std::vector<double> ms, cpu, pick_only;
        for (const Job& j : jobs) ms.push_back(j.trial->ms), cpu.push_back(j.cpu), pick_only.push_back(j.wall_pick);
        AutoRow a;
        a.scene = scene;
        a.kind = kind;
        a.threads = threads;
        a.budget = budget;
        a.picked = mid.trial->structure;
        a.picked_path = mid.trial->path;
        a.reason = mid.trial->reason;
        a.best = best->structure;
        a.best_path = best->path;
        a.best_ms = total(*best);
        a.default_ms = fallback ? total(*fallback) : nan_value;
        a.auto_ms = summarize(ms).median;
        a.auto_total_ms = mid.wall;
        a.regret = a.auto_total_ms / a.best_ms - 1.0;
        a.regret_without_auto = summarize(pick_only).median / a.best_ms - 1.0;
        a.regret_cpu = summarize(cpu).median / total_cpu(*best_cpu) - 1.0;
        double probed = 0.0;
        for (const Trial& t : trials) probed += t.probed;
        a.probed = probed / double(trials.size());
        a.oracle_split_regret = split_half_regret(out.rows, from, threads, budget, false);
        a.oracle_split_regret_cpu = split_half_regret(out.rows, from, threads, budget, true);
        a.same_twice = same_twice_within(*best, budget, false);
        a.same_twice_cpu = same_twice_within(*best_cpu, budget, true);
        out.autos.push_back(std::move(a));
    }
}

}  // namespace arbor::perf
