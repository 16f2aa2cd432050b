#pragma once
/// The Accel interface: one batch call, one virtual call per batch, static dispatch inside.
///
///   structure->trace(rays, hits, {Query::closest, TracePath::best});
///
/// trace() asks the path policy (interface/path_policy.h) when the request names no path the
/// structure offers, then makes the one virtual call, run(), into the structure, which dispatches
/// on the (query, path) statically down to its leaves' triangle tests. docs/architecture.md walks
/// one ray through it.
#include "accel/interface/build_config.h"
#include "accel/core/all_hits.h"
#include "accel/core/build_stats.h"
#include "accel/core/closest_point.h"
#include "accel/core/geometry.h"
#include "accel/core/query.h"
#include "accel/core/winding_tree.h"
#include "accel/core/refit.h"
#include "accel/interface/path_policy.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>

namespace arbor::accel {

enum class AccelKind { brute, bvh_median, bvh_sah, lbvh, kdtree, automatic };

std::string_view to_string(AccelKind k);
std::string_view to_string(TracePath p);
std::string_view to_string(Query q);
/// Parses "brute|bvh-median|bvh-sah|lbvh|kdtree|auto"; nullopt for anything else.
std::optional<AccelKind> parse_accel_kind(std::string_view s);
std::optional<TracePath> parse_trace_path(std::string_view s);
/// The names accepted by parse_accel_kind, for error messages: "brute, bvh-median, ...".
std::string accel_kind_names();

class Accel {
public:
    virtual ~Accel() = default;

    AccelKind kind() const { return kind_; }
    const BuildStats& stats() const { return stats_; }
    /// Records why this compact build replaced the default one (BuildStats::compact_fallback).
    void note_compact_fallback(std::string why) { stats_.compact_fallback = std::move(why); }
    /// The paths this build offers, the queries each answers, and what the path policy reads.
    const PathOffer& offer() const { return offer_; }

    /// The one batch call: answers `req.query` for rays[i] into hits[i] (hits.size() ==
    /// rays.size()) on req.path when the structure offers it for that query, else on the path the
    /// policy chooses; with req.counters, the counted mode (needs offer().counts, else throws
    /// std::logic_error). Untraceable rays (simd/ray.h) miss. Single-threaded: call from many
    /// threads on disjoint spans (trace.h does).
    void trace(std::span<const Ray> rays, std::span<Hit> hits, const TraceRequest& req = {}) const {
        TracePath path = req.path;
        if (req.counters) check_counts();
        else if (!offer_.runs(path, req.query)) path = choose_path(offer_, rays, req).path;
        run(rays, hits, req.query, path, req.counters);
    }

    /// All hits: every triangle each ray crosses in its whole [tnear, tfar] (never shortened), each
    /// triangle once, sorted by (t, prim), handed to sink.take(i, ...) ray by ray (all_hits.h).
    /// With the watertight test, a ray crossing a closed mesh away from its edges and vertices gets
    /// every crossing exactly once. Untraceable rays get an empty list. A call of its own, not a
    /// Query of trace(): its answer is a list per ray, not one Hit. Single-threaded; call from many
    /// threads on disjoint spans.
    virtual void trace_all(std::span<const Ray> rays, HitSink& sink) const = 0;
    /// Closest point: for each point, the nearest point of the scene within max_distance
    /// (closest_point.h; every structure returns the record brute force returns). Non-finite points
    /// and a negative max_distance get the miss record. Single-threaded, as above.
    virtual void closest_points(std::span<const Vec3f> points, float max_distance, std::span<PointHit> out) const = 0;
    /// The tree that answers generalized winding numbers for this structure (core/winding_tree.h),
    /// made now: call it on the first winding query and keep the result (a plain build makes
    /// none, so builds and traces cost the same as without winding numbers). `tris` are the
    /// triangles the structure was built over; the tree may read them (exact) and may read the
    /// structure's layout, so both must outlive it. The BVHs put a dipole on each child box of their
    /// own layout (no second tree); brute sums every triangle (it is the oracle, and builds
    /// nothing); this default, for the kd-tree, builds an internal BVH: the kd-tree lists a triangle in
    /// every leaf it crosses, so a sum over its leaves would count it more than once.
    virtual std::unique_ptr<WindingTree> make_winding_tree(const TriangleView& tris) const;

    /// Why this build cannot be refit, in a few words for a reason line ("a kd-tree's split planes
    /// cannot be refit"); empty when it can (refit()).
    virtual std::string_view refit_unsupported() const { return "this structure has no refit"; }
    /// Refits the build to `tris`: the triangles it was built over (the same indices, so the same
    /// triangle numbers) at new positions. The tree's topology is kept; the leaves' vertex copies
    /// are rewritten and every box recomputed bottom-up, so every query answers as a fresh build
    /// over `tris` would (bit for bit: the same triangle test on the same vertices, the same tie
    /// rule). Preconditions: refit_unsupported() is empty; the triangles finite now are exactly the
    /// ones finite at the build (a refit can neither add nor drop one). Not thread-safe: nothing
    /// else may use the structure meanwhile. The default throws std::logic_error.
    virtual RefitResult refit(const TriangleView& tris);

protected:
    explicit Accel(AccelKind kind) : kind_(kind) {}

    /// The structure's dispatch: `path` is offered and answers `query` (or, with `counters`, the
    /// counted mode is asked and offered).
    virtual void run(std::span<const Ray> rays, std::span<Hit> hits, Query query, TracePath path,
                     TraceCounters* counters) const = 0;

    AccelKind kind_;
    BuildStats stats_;
    PathOffer offer_;

private:
    void check_counts() const;
};

}  // namespace arbor::accel
