#pragma once
/// `--accel auto`: predicts, for this scene and ray budget, the build time and the trace time of
/// every structure this build provides, and picks the smallest total (build + budget rays).
///
/// The predictions come from a quick calibration at the current thread count:
/// - scenes up to AutoConfig::full_triangles: every structure is built on the whole scene (the
///   build time is measured, not predicted) and traces a sample of the rays;
/// - bigger scenes: every structure is built on a random subset of full_triangles triangles and
///   traces the sample there; the cheapest builder (lbvh) is also built on the whole scene and
///   traces the sample, which anchors the trace time at full size. A structure's predicted trace
///   time is the anchor's, scaled by its ratio to the anchor on the subset; its build time is the
///   subset build scaled by N log N (top-down builders) or N (lbvh).
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
};

struct AutoChoice {
    AccelKind kind = AccelKind::brute;
    std::string reason;                       ///< one line: the pick, its prediction, the runner-up
    std::vector<AutoPrediction> predictions;  ///< every candidate, smallest total first
    double calibration_ms = 0.0;              ///< wall time spent calibrating (builds + sample traces)
};

class AutoSelector {
public:
    /// Builds the calibration structures over `tris` (which must outlive the selector) with the
    /// current thread limit. Structures make_accel does not provide are skipped; throws
    /// std::invalid_argument when no structure at all can be built.
    explicit AutoSelector(const TriangleView& tris, const AutoConfig& cfg = {});
    ~AutoSelector();
    AutoSelector(const AutoSelector&) = delete;
    AutoSelector& operator=(const AutoSelector&) = delete;

    /// The pick for tracing `budget` rays like `sample` (closest hits, or any hit). An empty
    /// sample means rays from around the scene's bounds into it. Same as pick(predict(...)).
    AutoChoice choose(std::span<const Ray> sample, bool any_hit, double budget);
    /// Build and per-ray trace predictions of every candidate for rays like `sample` (traces the
    /// sample on every calibration structure; total_ms is left 0).
    std::vector<AutoPrediction> predict(std::span<const Ray> sample, bool any_hit);
    /// The pick among `predictions` for `budget` rays: totals filled, sorted, reason written.
    AutoChoice pick(std::vector<AutoPrediction> predictions, double budget) const;

    /// The structure of `kind` that calibration built on the whole scene, moved out (null when it
    /// was built on the subset only, or already taken).
    std::unique_ptr<Accel> take_built(AccelKind kind);

    /// Time spent so far (constructor and every choose()).
    double calibration_ms() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Rays from points on a sphere around `b` towards random points inside it (deterministic).
std::vector<Ray> rays_into_bounds(const Bounds& b, std::size_t n, std::uint64_t seed);

}  // namespace arbor::accel
