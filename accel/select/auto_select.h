#pragma once
/// `--accel auto`: predicts, for this scene and ray budget, the build time and the trace time of
/// every structure this build provides, and picks the smallest total (build + budget rays).
///
/// The predictions come from a quick calibration at the current thread count, whose cost follows
/// the budget (everything lazy, done at the first choose()/predict()):
/// - the anchor, lbvh (the cheapest build), is always built on the whole scene and traces the
///   sample. When the budget's trace time on it is at most AutoConfig::tiny_trace_fraction of its
///   build, no structure can beat it by more than that fraction (every other build is slower), and
///   it is picked without building anything else ("tiny budget");
/// - scenes up to AutoConfig::full_triangles: every structure is built on the whole scene (the
///   build time is measured, not predicted) and traces a sample of the rays;
/// - bigger scenes: every structure is built on a random subset of full_triangles triangles and
///   traces the sample there. A structure's predicted trace time is the anchor's whole-scene time,
///   scaled by its ratio to the anchor on the subset; its build time is the subset build scaled by
///   N log N (top-down builders) or N (lbvh). Then, when the budget is large enough, contenders
///   (predicted total within refine_margin of the best) whose predicted build costs at most
///   refine_fraction of the best total are built whole and timed there ("refined").
/// Every structure is timed through trace_parallel on each of its SIMD paths (packet and single;
/// scalar where it has none), and its faster path is part of the pick (AutoChoice::path): `arbor
/// trace --accel auto` runs the pick on that path. (TracePath::best decides by a coherence
/// measure alone, which misjudges some ray sets by up to 2x, perf/results/2026-11-22-simd.) Each timed
/// trace repeats the sample for at least min_timed_ms, so sub-millisecond traces are not timer
/// noise. Predicted totals within `tie` of the smallest count as a tie: then the cheapest build
/// wins when the build is most of the total, else bvh-sah (the most robust tree) when it is tied.
/// Structures built on the whole scene during calibration can be taken over (take_built), so a
/// pick of one of them costs no second build.
#include "accel/accel.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace arbor::accel {

struct AutoConfig {
    /// Scenes up to this many triangles are calibrated whole; bigger ones on a subset this large.
    std::size_t full_triangles = 32768;
    /// Rays of the sample traced by each calibration structure: a longer sample is cut into
    /// ceil(sample_rays / 256) runs of 256 consecutive rays spread evenly over it (coherent rays
    /// stay coherent).
    std::size_t sample_rays = 4096;
    /// Timed traces of the sample per structure; the fastest counts (the least disturbed).
    int repeats = 3;
    /// One timed trace repeats the sample until this much wall time has passed (ns/ray = time /
    /// rays traced): a 4096-ray shadow batch can take 0.1 ms, where scheduling noise dominates.
    double min_timed_ms = 4.0;
    /// Budget ray time on the anchor at most this fraction of its build: picked without calibrating
    /// the others (see the header comment).
    double tiny_trace_fraction = 0.05;
    /// Refinement of subset predictions (scenes above full_triangles): contenders within
    /// refine_margin of the best predicted total whose predicted build is at most refine_fraction of
    /// it are built on the whole scene and timed there.
    double refine_margin = 0.25, refine_fraction = 0.10;
    /// Calibration builds faster than this (ms) are built twice, the faster time kept.
    double rebuild_below_ms = 100.0;
    /// Predicted totals within this fraction of the smallest are a tie (the calibration's noise).
    double tie = 0.05;
    /// brute is a candidate only up to this many triangles.
    std::size_t brute_triangles = 256;
    BuildConfig build;
    std::uint64_t seed = 1;
};

struct AutoPrediction {
    AccelKind kind = AccelKind::brute;
    double build_ms = 0.0;    ///< predicted (or measured, when built whole) build time
    double ns_per_ray = 0.0;  ///< predicted trace time per ray at the current thread count
    double total_ms = 0.0;    ///< build_ms + budget * ns_per_ray
    bool built_whole = false; ///< calibration built it on the whole scene
    TracePath path = TracePath::scalar;  ///< its fastest path on the sample (ns_per_ray is on it)
};

struct AutoChoice {
    AccelKind kind = AccelKind::brute;
    TracePath path = TracePath::scalar;       ///< the pick's fastest path on the calibration sample: trace on it
    std::string reason;                       ///< one line: the pick, its prediction, the runner-up
    std::vector<AutoPrediction> predictions;  ///< every candidate, smallest total first
    double calibration_ms = 0.0;              ///< wall time spent calibrating (builds + sample traces)
};

class AutoSelector {
public:
    /// Builds the anchor over the whole of `tris` (which must outlive the selector) with the current
    /// thread limit; the other calibration structures follow when first needed. Structures
    /// make_accel does not provide are skipped; throws std::invalid_argument when no structure at
    /// all can be built.
    explicit AutoSelector(const TriangleView& tris, const AutoConfig& cfg = {});
    ~AutoSelector();
    AutoSelector(const AutoSelector&) = delete;
    AutoSelector& operator=(const AutoSelector&) = delete;

    /// The pick for tracing `budget` rays like `sample` (closest hits, or any hit). An empty
    /// sample means rays from around the scene's bounds into it. The tiny-budget shortcut, then
    /// pick(refine(predict(...))).
    AutoChoice choose(std::span<const Ray> sample, bool any_hit, double budget);
    /// The tiny-budget shortcut alone: the anchor's choice when the budget's trace time on it is
    /// at most cfg.tiny_trace_fraction of its build (times the sample on the anchor only), else a
    /// choice with no predictions.
    AutoChoice choose_tiny(std::span<const Ray> sample, bool any_hit, double budget);
    /// Build and per-ray trace predictions of every candidate for rays like `sample` (calibrates
    /// the candidates on first use, traces the sample on every calibration structure; total_ms is
    /// left 0).
    std::vector<AutoPrediction> predict(std::span<const Ray> sample, bool any_hit);
    /// Subset calibration only: builds the contenders for `budget` rays whole (see the header
    /// comment) and, when it built any, predicts again; else returns `predictions` unchanged.
    std::vector<AutoPrediction> refine(std::vector<AutoPrediction> predictions, std::span<const Ray> sample,
                                       bool any_hit, double budget);
    /// The pick among `predictions` for `budget` rays: totals filled, sorted by total, the tie rule
    /// applied (the pick need not be the first), reason written. Deterministic.
    AutoChoice pick(std::vector<AutoPrediction> predictions, double budget) const;

    /// The structure of `kind` that calibration built on the whole scene, moved out (null when it
    /// was built on the subset only, or already taken).
    std::unique_ptr<Accel> take_built(AccelKind kind);

    /// Time spent so far (constructor, every predict(), refine() and choose()).
    double calibration_ms() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// The work `--accel auto` picks a structure for.
struct AutoWork {
    std::span<const Ray> sample;       ///< rays like those to be traced (empty: rays into the bounds)
    Query query = Query::closest;
    double budget = double(1 << 20);   ///< rays to be traced
    BuildConfig build;                 ///< the settings the pick will be built with
};

/// What a structure name resolved to, for `work`.
struct AccelPick {
    AccelKind kind = AccelKind::brute;
    /// The pick's fastest path in auto's calibration (best: not calibrated); the path policy takes
    /// it for `best` (TraceRequest::calibrated).
    TracePath path = TracePath::best;
    std::string reason;                ///< auto's one line: the pick, its prediction, the runner-up
    std::unique_ptr<Accel> built;      ///< the pick, when calibration built it on the whole scene
    double calibration_ms = 0.0;       ///< time auto spent calibrating
};

/// `kind` as it is, or for `automatic`: an AutoSelector over `tris` (which must outlive the call)
/// calibrated on `work`, its choice, and the pick when calibration built it whole.
AccelPick pick_accel(AccelKind kind, const TriangleView& tris, const AutoWork& work = {});

/// Rays from points on a sphere around `b` towards random points inside it (deterministic).
std::vector<Ray> rays_into_bounds(const Bounds& b, std::size_t n, std::uint64_t seed);

}  // namespace arbor::accel
