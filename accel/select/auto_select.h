#pragma once
/// `--accel auto`: the one decision every caller makes the same way (`arbor trace`, `render`,
/// `converge`, `info`, `rays`, the C++ API and the Python module): pick_accel() on an AutoJob,
/// which holds only what is known before building (the triangles, the ray groups' counts, queries,
/// coherence and paths, the build settings, the thread count of the calling arena).
///
/// How it decides (docs/auto.md, "How it decides"):
///  1. The cost model (auto_model.h) predicts, for every structure and path, build + trace time of
///     the whole job from the scene's and the rays' shape (job_shape.h): microseconds of work.
///  2. Configurations predicted within the model's margin of the best are its contenders. When there
///     is one, it is the pick ("model").
///  3. Else, when the job is large enough, a probe settles it: the contenders' structures are built
///     whole and a sample of the rays is timed on each contender (on the calling thread, its CPU
///     time / threads, the faster of two interleaved rounds: auto_probe.h), and the pick is the smallest measured build + trace total.
///     The probe is capped at AutoJob::probe_share (2%) of the job's predicted time, counted as the
///     builds the pick will not reuse plus the sample traces, and at AutoJob::stake_share (1/4) of
///     what it can win (the margin times the contenders' unshared part of the job: when they are
///     two paths of one structure, the trace alone); contenders whose builds do not fit
///     are dropped (costliest first), and a job whose cap cannot pay for timings long enough to
///     measure (AutoJob::min_timing_ms each) is decided by the model alone: a tiny job takes no
///     calibration at all. The pick's structure, when the probe built it, is handed over (built).
/// The reason says which of these decided, with the prediction and margin or the probe's figures.
/// The model's decision is deterministic (same job, same pick and reason); a probe measures.
#include "accel/interface/accel.h"
#include "accel/select/job_shape.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace arbor::accel {

class AutoModel;

/// One kind of rays of a job: its shape (count, query, coherence, the path it will run on, or
/// best: auto picks) and, when at hand, a sample of such rays for the probe.
struct RayGroup {
    RayShape shape;
    std::span<const Ray> sample;
    std::string name;  ///< for the reason ("camera", "shadow", ...); may be empty
};

/// What auto decides for.
struct AutoJob {
    TriangleView tris;
    /// The job's rays; empty: default_rays closest-hit rays into the scene's bounds.
    std::vector<RayGroup> groups;
    BuildConfig build;  ///< the settings the pick will be built with (the probe builds with them)
    /// Threads the job runs on; 0: the calling arena's (and global_control's) limit.
    int threads = 0;
    /// The probe's cap, as a share of the job's predicted time.
    double probe_share = 0.02;
    /// A timing of the probe traces at least this long (predicted) to be worth measuring.
    double min_timing_ms = 0.25;
    /// The probe's second cap, as a share of what it can win: the model's margin times the part of
    /// the job its contenders do not share (a build every contender needs is paid whatever the
    /// probe finds). Two paths of one structure on 1,000 rays differ by microseconds: no probe.
    double stake_share = 0.25;
    bool allow_probe = true;
    /// The model; null: builtin_auto_model().
    const AutoModel* model = nullptr;

    static constexpr double default_rays = double(1 << 20);
};

/// One configuration auto weighed: a structure and the path of the groups whose path it picks.
struct AutoCandidate {
    AccelKind kind = AccelKind::bvh_sah;
    TracePath path = TracePath::best;   ///< best when every group's path is fixed
    double build_ms = 0.0;              ///< predicted (or measured by the probe)
    double trace_ms = 0.0;              ///< predicted (or measured) trace time of all the job's rays
    double total_ms = 0.0;
    bool probed = false;                ///< build_ms and trace_ms are the probe's
};

/// What a structure name resolved to.
struct AccelPick {
    AccelKind kind = AccelKind::bvh_sah;
    /// The path auto picked for the groups whose path was free (best: none, or not auto); the path
    /// policy takes it for `best` (TraceRequest::calibrated).
    TracePath path = TracePath::best;
    std::string reason;                 ///< auto's one line (empty when a structure was named)
    std::unique_ptr<Accel> built;       ///< the pick, when the probe built it with AutoJob::build
    double auto_ms = 0.0;               ///< wall time auto spent: shapes, model, probe
    /// auto_ms less the build of the pick it handed over (`built`), which the job needs anyway:
    /// auto's own work, what it costs over a fixed choice of the same structure.
    double own_ms = 0.0;
    bool probed = false;                ///< a probe ran
    std::vector<AutoCandidate> candidates;  ///< every configuration, smallest total first
};

/// `kind` as it is, or for `automatic` the decision above. Throws std::invalid_argument when the
/// job's settings can be built by none of the model's structures.
AccelPick pick_accel(AccelKind kind, const AutoJob& job);

/// A one-group job: `count` rays like `sample` (empty: rays into the bounds), answering `query`,
/// on `path` (best: auto picks it). Measures the sample's coherence (job_shape.h).
AutoJob trace_job(const TriangleView& tris, std::span<const Ray> sample, double count, Query query,
                  TracePath path = TracePath::best, const BuildConfig& build = {});

/// Threads a parallel trace runs on here and now (the arena's and global_control's limits).
int active_trace_threads();

/// Rays from points on a sphere around `b` towards random points inside it (deterministic).
std::vector<Ray> rays_into_bounds(const Bounds& b, std::size_t n, std::uint64_t seed);

}  // namespace arbor::accel
