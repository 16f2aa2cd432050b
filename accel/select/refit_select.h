#pragma once
/// Refit or rebuild, when a mesh's vertices move (the C++ API's Scene::update_vertices, Python's
/// scene.update_vertices): the decision and its one-line reason, as pick_accel (auto_select.h)
/// gives `--accel auto`'s.
///
/// A refit (Accel::refit) keeps the tree and recomputes its boxes: cheap (one pass over the
/// triangles), but the old splits may suit the new positions badly, and every ray then pays for
/// the looser boxes. A rebuild pays a whole build and gets a tree made for the new positions. The
/// decision weighs the two on the work the tree will do before the next update:
///
///   keep the refit:  rays x ns_fresh x ratio            (the refit is done already)
///   rebuild:         rebuild_ms + rays x ns_fresh
///
/// where ratio = the refitted tree's SAH cost / the SAH cost of the tree as last built (the
/// estimate of a fresh build's cost: RefitResult), ns_fresh the trace time per ray on a fresh
/// tree, and rebuild_ms the last build's measured time. So it rebuilds when the rays' extra time on
/// the refitted tree, rays x ns_fresh x (ratio - 1), exceeds a rebuild. A trace's time follows the
/// SAH cost (the expected number of node and triangle tests per ray, MacDonald and Booth 1990)
/// closely enough for the comparison; docs/refit.md shows it on the benchmark.
#include "accel/core/refit.h"

#include <optional>
#include <string>
#include <string_view>

namespace arbor::accel {

/// What update_vertices is asked to do: decide (automatic), or always refit, or always rebuild.
enum class UpdateMode { automatic, refit, rebuild };

/// "auto", "refit", "rebuild"; nullopt for anything else.
std::optional<UpdateMode> parse_update_mode(std::string_view s);

/// What the decision knows after the refit (automatic mode refits first: the refitted tree's cost
/// is the measurement, and the refit itself is a small part of a rebuild).
struct RefitJob {
    RefitResult refit;
    /// Rays expected on the tree before the next update, and where the number comes from
    /// ("given", "traced since the last update").
    double rays = 0.0;
    std::string rays_source;
    /// Trace time per ray on a freshly built tree, ns, and where it comes from ("measured",
    /// "predicted by auto's model").
    double ns_per_ray = 0.0;
    std::string ns_source;
    /// The rebuild's predicted time: the last build's measured one.
    double rebuild_ms = 0.0;
};

struct RefitChoice {
    bool rebuild = false;
    /// One line: "refit: ..." or "rebuild: ...", with the figures that decided.
    std::string reason;
    /// rays x ns_fresh x (ratio - 1): what the refitted tree costs the rays over a fresh one, ms.
    double extra_trace_ms = 0.0;
};

/// The automatic decision (deterministic: the same job gives the same choice and reason).
RefitChoice choose_refit(const RefitJob& job);

/// The reason of a forced choice: "refit: asked for (mode refit); SAH 1.07x the last build's" or
/// "rebuild: asked for (mode rebuild)". `refit` is the refit's result when one was made.
std::string forced_reason(UpdateMode mode, const RefitResult* refit);

/// The reason when the structure cannot be refit: "rebuild: <why>".
std::string unsupported_reason(std::string_view why);

/// "1.07x": a SAH ratio as the reasons print it.
std::string ratio_words(double ratio);

}  // namespace arbor::accel
