#pragma once
/// The path policy: the one place where a trace path is chosen. Accel::trace asks it when a batch
/// comes with `best` (or a path the structure does not offer); `arbor trace` asks it once for the
/// whole ray file to report `path` and `path_reason`; the renderer's batches bring a RayHint. It
/// also says which layouts a build needs for a path (`arbor trace` builds only what its path
/// reads) and what such a build leaves out.
///
/// The rule, in order:
///   1. an offered path that answers the query, asked for by name, is taken ("forced");
///   2. the path --accel auto picked for these rays (TraceRequest::calibrated; its reason says why);
///   3. a structure with one path takes it (brute; a build with the scalar layout only);
///   4. a structure whose packets do not pay (PathOffer::packets_pay; none today) takes `single`;
///   5. a hint decides: coherent batches take `packet`, incoherent ones `single`;
///   6. else the rays are measured (coherence.h): `packet` when at least half of the groups of
///      consecutive rays that would share a packet start within 5% of the scene's diagonal of each
///      other (one direction octant, or, failing that, any), else `single`
///      (measured on the benchmark's ray files, docs/benchmarks.md); any-hit rays that would go single
///      take `packet` when half of the groups share an octant, or end together (shadow rays
///      towards one point light).
#include "accel/interface/build_config.h"
#include "accel/core/query.h"
#include "accel/core/ray.h"

#include <span>
#include <string>
#include <vector>

namespace arbor::accel {

enum class AccelKind;

/// The policy's answer: the path, and why (path_reason turns it into one line).
struct PathChoice {
    enum class Why : std::uint8_t { forced, calibrated, only_path, only_scalar_built, packets_do_not_pay, hint, measured };
    TracePath path = TracePath::scalar;
    Why why = Why::only_path;
    /// The path asked for by name when it was not offered (best otherwise).
    TracePath not_offered = TracePath::best;
    RayHint hint = RayHint::unknown;
    /// Measured (why == measured): rays per group, and the fractions of groups that are coherent
    /// (one octant, origins together) and that start together (origins only; = coherent when
    /// `one_octant`).
    std::uint32_t group = 0;
    double coherent = 0.0, together = 0.0;
    bool one_octant = false;
    /// Any-hit queries that would go single: the fraction of groups in one octant, origins anywhere.
    double octant_only = 0.0;
    /// Any-hit queries in neither case: the fraction of groups whose rays end together (org + tfar
    /// * dir within 5% of the scene's diagonal: shadow rays towards one point light).
    double end_together = 0.0;
};

/// The path for `rays` on a structure offering `offer`, asked as `req` (query, path, hint,
/// calibrated path; req.counters is not read). Cheap: at most 16 groups of rays are looked at.
PathChoice choose_path(const PathOffer& offer, std::span<const Ray> rays, const TraceRequest& req);

/// The rays of a batch of `n` that choose_path reads on a structure offering `offer` (a few groups of
/// packet_lanes consecutive rays, spread over the batch), in order: choose_path over just these
/// rays, gathered, answers as over the whole batch. For callers whose rays are not Ray records yet
/// (the public API's arrays), so that a batch gets one path decision without converting it first.
std::vector<std::size_t> policy_sample(const PathOffer& offer, std::size_t n);

/// One line saying why (`arbor trace --json`'s path_reason).
std::string path_reason(const PathChoice& c);

/// The layouts a build needs to trace on `path`: the reference layout for `scalar`, the SIMD
/// layouts for anything else (best takes a SIMD path when it has one).
Layouts layouts_for(TracePath path);


}  // namespace arbor::accel
