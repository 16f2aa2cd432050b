#pragma once
/// The benchmark's results: one row per (scene, ray kind, threads, structure, path), the auto
/// choices, and notes. Written by bench_report.h as JSON, CSV and Markdown.
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace arbor::perf {

inline constexpr double nan_value = std::numeric_limits<double>::quiet_NaN();

/// Median, minimum and maximum of repeated measurements.
struct Stat3 {
    double median = nan_value, min = nan_value, max = nan_value;
};
/// Of `v` (empty: all NaN). The median of an even count is the mean of the middle two.
Stat3 summarize(std::vector<double> v);

struct BenchRow {
    std::string scene, family, kind, query;  ///< query: closest or any (shadow rays)
    std::string structure;                   ///< arbor structure name, or embree[-high][-robust]
    std::string path;                        ///< scalar|packet|single, or the Embree call 1|8|16|1M
    /// The path TracePath::best takes on most chunks of these rays (what `arbor trace`, the
    /// renderer and --accel auto run); false on Embree rows.
    bool best_path = false;
    bool embree = false;
    int threads = 0;
    std::string host;   ///< the machine that measured the row
    int rank = -1;      ///< the MPI rank that measured it (`mpirun arbor bench`), -1 without MPI
    std::size_t triangles = 0;
    std::size_t rays = 0;            ///< rays timed
    std::size_t validated_rays = 0;  ///< rays of the error columns (the timed ones or a finer image of them)

    Stat3 build_ms;  ///< wall time of the build at this thread count (Embree: rtcCommitScene)
    Stat3 trace_ms;  ///< wall time of tracing all rays
    Stat3 mrays;     ///< rays / trace time, in millions per second (min from the slowest run)
    std::vector<double> build_samples, trace_samples;  ///< every build / timed trace, ms, in run order
    /// Process CPU time of each timed trace divided by the thread count, ms (in run order): the
    /// wall time the trace would take on an otherwise idle machine (perfect parallel speed-up),
    /// untouched by the time other jobs hold the cores.
    std::vector<double> trace_cpu_samples;
    Stat3 trace_cpu_ms;

    // Structure statistics (NaN / 0 when the structure does not report them).
    double nodes = nan_value, leaves = nan_value, max_depth = nan_value, sah_cost = nan_value;
    double bytes_per_triangle = nan_value;
    /// Statistics mode (TraceCounters) on a sample of the rays; NaN when the structure does not count.
    double nodes_per_ray = nan_value, tris_per_ray = nan_value;

    // The error columns.
    std::size_t brute_sample = 0;  ///< rays of the brute-force sample
    long long err_brute = -1;      ///< of them, answers disagreeing with brute (rayfile.md rule)
    long long err_scalar = -1;     ///< all rays: disagreeing with this structure's scalar path (-1: is scalar)
    long long err_embree = -1;     ///< all rays: disagreeing with Embree default, rtcIntersect1 (-1: no Embree)

    double ratio_embree = nan_value;  ///< median Mrays/s over Embree default's best call (same scene, kind, threads)
    std::vector<double> total_ms;     ///< build + trace time for each ray budget of the run
    /// The same from the fastest build and the median CPU-time trace (trace_cpu_ms).
    std::vector<double> total_cpu_ms;
    /// What --accel auto knows of this (scene, kind) before building (accel/select/job_shape.h):
    /// the numbers its cost model reads, so that the model can be fitted from this output.
    std::vector<std::pair<std::string, double>> shape;
};

/// One (scene, kind, threads, budget) row of --accel auto against the measured matrix
/// (perf/bench_auto.h): the whole job by the wall clock, auto's own work counted.
struct AutoRow {
    std::string scene, kind;
    int threads = 0;
    double budget = 0.0;
    std::string picked, picked_path;  ///< auto's pick (of the median trial) and the path it runs
    std::string best, best_path;      ///< the fixed (structure, path) with the smallest total
    double auto_ms = 0.0;             ///< auto's own wall time (median of the trials)
    double auto_total_ms = 0.0;       ///< median over the trials of auto's time + its pick's build and trace
    double best_ms = 0.0;             ///< the smallest build + trace total of any fixed (structure, path)
    double default_ms = 0.0;          ///< the default's total: bvh-sah on the path best takes
    double regret = 0.0;              ///< auto_total_ms / best_ms - 1: THE measure
    double regret_without_auto = 0.0; ///< the same without auto's own time (the pick alone)
    /// By CPU time: auto's CPU time / threads + the pick's fastest build + budget x its median
    /// trace CPU time / threads, over the smallest such total of any fixed choice, - 1.
    double regret_cpu = 0.0;
    double probed = 0.0;              ///< share of the trials in which a probe ran
    /// Noise floors: an oracle that picks on half of the repeats, judged on the other half (its
    /// regret); and whether the best fixed choice measured twice (even and odd repeats) is within
    /// 10% of itself. Wall clock and CPU time.
    double oracle_split_regret = 0.0, oracle_split_regret_cpu = 0.0;
    bool same_twice = false, same_twice_cpu = false;
    std::string reason;  ///< auto's reason (median trial)
};

struct BenchResult {
    std::vector<BenchRow> rows;
    std::vector<AutoRow> autos;
    std::vector<std::string> notes;      ///< unavailable structures, skipped scenes, ...
    std::vector<double> budgets;
    std::string embree;                  ///< embree_description(), or "not built"
    std::string compiler, libraries, command, date;
    std::string load_before, load_after;  ///< /proc/loadavg at the start and the end (a shared machine)
    int hardware_threads = 0;
    double seconds = 0.0;                ///< wall time of the whole run
};

}  // namespace arbor::perf
