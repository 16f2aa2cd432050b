#pragma once
/// The cost model of `--accel auto`: build time and trace time per ray of every (structure, path),
/// predicted from the job's shape alone (job_shape.h) before anything is built.
///
/// Both are log-linear: ln(ns per ray) = c . x and ln(build ms) = b . x over named features x of
/// the scene, the rays and the thread count (feature_value()). The coefficients, the features'
/// training ranges (a feature is clamped to its range, so a scene unlike any the model saw is
/// predicted like the nearest one it did, not extrapolated) and the margin come from a text file
/// fitted on the benchmark's own output: perf/model/auto_model.txt, written by
/// perf/model/fit_auto_model.py from the bench.json kept beside it, and compiled into the library
/// (builtin_auto_model()). Issue 20's faster traces: rerun the benchmark and the script.
#include "accel/core/query.h"
#include "accel/select/job_shape.h"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace arbor::accel {

enum class AccelKind;

/// The value of the named feature for this scene, rays and thread count; nullopt for an unknown
/// name. Names: one, log2_triangles, log_overlap, log_spread, log_size_tail, log_thinness,
/// coherent, together, any_hit, log2_threads.
std::optional<double> feature_value(std::string_view name, const SceneShape& scene, const RayShape& rays, double threads);

class AutoModel {
public:
    /// Parses the text format of perf/model/auto_model.txt; throws std::invalid_argument naming the
    /// line on anything malformed (unknown keyword, feature or structure, wrong coefficient count).
    static AutoModel parse(std::string_view text);

    /// Whether the model has trace times of `kind` on `path`, and a build time of `kind`.
    bool has(AccelKind kind, TracePath path) const;
    /// Predicted trace time per ray, ns (has(kind, path) must hold).
    double ns_per_ray(AccelKind kind, TracePath path, const SceneShape& scene, const RayShape& rays, double threads) const;
    /// Predicted build time, ms.
    double build_ms(AccelKind kind, const SceneShape& scene, double threads) const;
    /// Structures with a build time and at least one path, in the file's order.
    std::vector<AccelKind> structures() const;

    /// How far (as a fraction of the smaller) two predicted totals must be apart for the model to
    /// tell them apart: a quantile of the fit's errors on ratios between configurations.
    double margin() const { return margin_; }
    /// The structure whose best configuration the model's decision takes over the predicted best
    /// when it is predicted within prefer_share() of it (the file's `prefer STRUCTURE SHARE` line;
    /// share 0, or no line: none). Fitted like the margin: the share that does best leaving each
    /// scene out (perf/model/fit_auto_model.py).
    AccelKind preferred() const { return preferred_; }
    double prefer_share() const { return prefer_share_; }
    /// One line: where the model came from (the file's `source` line).
    const std::string& source() const { return source_; }

private:
    struct Linear {
        std::vector<double> coef;  // one per feature of its list
    };
    struct Trace {
        AccelKind kind;
        TracePath path;
        Linear fit;
    };
    struct Build {
        AccelKind kind;
        Linear fit;
    };
    struct Clamp {
        std::string feature;
        double lo, hi;
    };
    double eval(const Linear& l, const std::vector<std::string>& features, const SceneShape& scene, const RayShape& rays,
                double threads) const;

    std::vector<std::string> trace_features_, build_features_;
    std::vector<Clamp> clamps_;
    std::vector<Trace> trace_;
    std::vector<Build> build_;
    double margin_ = 0.25;
    AccelKind preferred_{};
    double prefer_share_ = 0.0;
    std::string source_;
};

/// The model compiled into this library (perf/model/auto_model.txt), parsed on first use.
const AutoModel& builtin_auto_model();

}  // namespace arbor::accel
