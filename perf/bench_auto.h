#pragma once
/// `--accel auto` judged as a user feels it: the wall clock of the whole job. For each (scene,
/// kind, threads, budget) the benchmark asks auto's one decision (accel::pick_accel) for a job of
/// `budget` rays like this kind's, once per timing repeat, interleaved with the timings of the
/// fixed (structure, path) configurations, and times the call (shapes, model, probe builds and
/// traces). Auto's job total is then
///     auto's own wall time + the pick's build (unless the probe built it) + budget x its trace time,
/// from the pick's measured row (medians of the repeats), the median over the repeats; the best
/// fixed choice's total is build + budget x trace time of the best row, the same way.
#include "accel/select/auto_select.h"
#include "perf/bench_options.h"
#include "perf/bench_result.h"

#include <map>
#include <span>
#include <string>
#include <vector>

namespace arbor::perf {

class AutoEvaluator {
public:
    /// Decisions for `rays` (answering `query`) over `tris`, built with `build`, for each budget.
    AutoEvaluator(const accel::TriangleView& tris, std::span<const accel::Ray> rays, accel::Query query,
                  const accel::BuildConfig& build, std::vector<double> budgets);

    /// One decision per budget at `threads` (the caller's thread limit), each timed.
    void run(int threads);

    /// The rays the decisions are about from now on: the ones the fixed configurations are timed
    /// on, when that is a smaller set (a coarser image) than the validated rays.
    void set_rays(std::span<const accel::Ray> rays) { rays_ = rays; }

    /// Judges the decisions made at each thread count against rows [from, end) of `out` (this
    /// scene and kind) and appends one AutoRow per (threads, budget) to out.autos.
    void judge(const std::string& scene, const std::string& kind, std::size_t from, BenchResult& out) const;

private:
    struct Trial {
        double ms = 0.0, cpu_ms = 0.0;  ///< auto's wall time; its process CPU time / threads
        std::string structure, path;    ///< the pick and the path it runs (best: the policy's)
        bool built = false, probed = false;
        std::string reason;
    };
    accel::TriangleView tris_;
    std::span<const accel::Ray> rays_;
    accel::Query query_;
    accel::BuildConfig build_;
    std::vector<double> budgets_;
    std::map<std::pair<int, std::size_t>, std::vector<Trial>> trials_;  ///< (threads, budget index)
};

/// The noise floor "the same choice measured twice": whether the totals of `row` from its
/// even-numbered and odd-numbered repeats (wall, or CPU time) lie within 10% of each other.
/// False with fewer than 2 repeats.
bool same_twice_within(const BenchRow& row, double budget, bool cpu);

}  // namespace arbor::perf
