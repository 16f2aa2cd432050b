#pragma once
/// The Accel interface: one virtual call per batch of rays, static dispatch inside.
#include "accel/core/all_hits.h"
#include "accel/core/build_config.h"
#include "accel/core/build_stats.h"
#include "accel/core/closest_point.h"
#include "accel/core/geometry.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace arbor::accel {

enum class AccelKind { brute, bvh_median, bvh_sah, lbvh, kdtree, automatic };

/// How a batch is traced. `scalar` is the reference path of every structure; `packet` traces
/// SIMD ray packets (coherent rays); `single` traces one ray at a time over SIMD node/leaf tests.
/// `best` lets the structure pick.
enum class TracePath { best, scalar, packet, single };

std::string_view to_string(AccelKind k);
std::string_view to_string(TracePath p);
/// Parses "brute|bvh-median|bvh-sah|lbvh|kdtree|auto"; nullopt for anything else.
std::optional<AccelKind> parse_accel_kind(std::string_view s);
std::optional<TracePath> parse_trace_path(std::string_view s);
/// The names accepted by parse_accel_kind, for error messages: "brute, bvh-median, ...".
std::string accel_kind_names();

/// What a traversal did, summed over the rays of a batch: the statistics mode of the benchmarks
/// (perf/README.md, "Counting hook"). A structure that counts fills all three fields with its
/// scalar reference loop; the counting loop is a separate instantiation (e.g. a `bool Count`
/// template parameter), so the timed paths carry no counter code.
struct TraceCounters {
    std::uint64_t rays = 0;              ///< rays of the batches counted (traceable or not)
    std::uint64_t nodes_visited = 0;     ///< nodes whose contents a ray read: interior nodes whose
                                         ///< child boxes (or split plane) it tested, and leaves it entered
    std::uint64_t triangles_tested = 0;  ///< ray/triangle tests performed

    TraceCounters& operator+=(const TraceCounters& o) {
        rays += o.rays, nodes_visited += o.nodes_visited, triangles_tested += o.triangles_tested;
        return *this;
    }
};

class Accel {
public:
    virtual ~Accel() = default;

    virtual AccelKind kind() const = 0;
    virtual const BuildStats& stats() const = 0;
    /// Whether this structure has its own implementation of `path` (others fall back to scalar).
    virtual bool has_path(TracePath path) const { return path == TracePath::scalar || path == TracePath::best; }

    /// The path `best` takes for this batch of rays (never `best`), and in `reason` (when given)
    /// why. The default is the scalar path.
    virtual TracePath resolve_path(std::span<const Ray> rays, bool any_hit, std::string* reason = nullptr) const {
        if (reason) *reason = "the only path of this structure";
        return TracePath::scalar;
    }

    /// Closest hit for each ray (hits.size() == rays.size()). Single-threaded; call from many
    /// threads on disjoint spans (see trace.h). Untraceable rays (ray_is_traceable) miss.
    virtual void intersect(std::span<const Ray> rays, std::span<Hit> hits, TracePath path) const = 0;
    /// Any hit in [tnear, tfar] for each ray: t and prim of some hit, or the miss record.
    virtual void occluded(std::span<const Ray> rays, std::span<Hit> hits, TracePath path) const = 0;

    /// All hits: every triangle each ray crosses in its whole [tnear, tfar] (never shortened), each
    /// triangle once, sorted by (t, prim), handed to sink.take(i, ...) ray by ray (all_hits.h).
    /// With the watertight test, a ray crossing a closed mesh away from its edges and vertices gets
    /// every crossing exactly once. Single-threaded; call from many threads on disjoint spans.
    /// Untraceable rays get an empty list.
    virtual void trace_all(std::span<const Ray> rays, HitSink& sink) const = 0;
    /// Closest point: for each point, the nearest point of the scene within max_distance
    /// (closest_point.h; every structure returns the record brute force returns). Non-finite points
    /// and a negative max_distance get the miss record. Single-threaded, as above.
    virtual void closest_points(std::span<const Vec3f> points, float max_distance, std::span<PointHit> out) const = 0;

    /// Statistics mode: the same answers as intersect (any_hit = false) or occluded (true) on the
    /// scalar path, while adding what the traversal did to `counters`. Returns false, leaving
    /// hits and counters untouched, when the structure does not count (the default).
    virtual bool trace_counted(std::span<const Ray> rays, std::span<Hit> hits, bool any_hit,
                               TraceCounters& counters) const {
        return false;
    }
};

/// Builds structure `kind` over `tris`. The view must outlive the Accel only for `brute`
/// (the others copy what they need). `automatic` is resolved by the caller (auto_select.h).
/// With cfg.max_memory set, a build whose estimate (memory_estimate.h) exceeds it throws
/// MemoryLimitError before anything is allocated.
std::unique_ptr<Accel> make_accel(AccelKind kind, const TriangleView& tris, const BuildConfig& cfg = {});

}  // namespace arbor::accel
