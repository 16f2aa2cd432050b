#pragma once
/// What a batch of rays asks of a structure (TraceRequest: the query kind, the path, what the caller
/// knows of the rays, the counted mode) and what a structure offers (PathOffer). Accel::trace takes
/// the first, Accel::offer gives the second, and the path policy (interface/path_policy.h) reads both:
/// it is the one place where a path is chosen.
///
/// Adding a query kind (e.g. all hits): add it to Query (and to query_names in accel.cpp), set its
/// bit in PathOffer::queries for each path that answers it (in each structure's constructor),
/// answer it in each structure's run() (brute/, bvh/, kdtree/; the SIMD paths dispatch in
/// core/simd_paths.h), and give it a HitRecord in core/hit_record.h if it keeps hits differently.
/// A path that does not answer a query is never given it: the policy falls back to one that does.
#include <cstdint>

namespace arbor::accel {

/// How a batch is traced. `scalar` is the reference path of every structure; `packet` traces
/// SIMD ray packets (coherent rays); `single` traces one ray at a time over SIMD node/leaf tests.
/// `best` lets the path policy pick.
enum class TracePath : std::uint8_t { best, scalar, packet, single };
inline constexpr unsigned trace_path_count = 4;

/// The query kind: the closest hit of each ray (t, prim, u, v; on equal t the lowest prim, see
/// core/hit_record.h), or any hit in [tnear, tfar] (t and prim of some hit; a shadow ray's question).
enum class Query : std::uint8_t { closest, any };
inline constexpr unsigned query_count = 2;

/// What the caller knows of the rays' coherence: `coherent` (camera rays of a tile, shadow rays
/// from a tile towards one light), `incoherent` (bounces), or `unknown` (the policy measures them).
enum class RayHint : std::uint8_t { unknown, coherent, incoherent };

/// What a traversal did, summed over the rays of a batch: the counted mode (perf/README.md,
/// "For structure owners"; a per-pixel cost image traces one ray per batch). A structure counts with its
/// scalar reference loop; the counting loop is its own instantiation (a `bool Count` template
/// parameter), so the other paths carry no counter code.
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

/// One batch call's request (Accel::trace, trace_parallel). Every field has a default, so
/// `{Query::any}` or `{Query::closest, TracePath::packet}` read as what they ask.
struct TraceRequest {
    Query query = Query::closest;
    /// The path asked for; `best`, or a path the structure does not offer, lets the policy choose.
    TracePath path = TracePath::best;
    RayHint hint = RayHint::unknown;
    /// A path `--accel auto`'s calibration timed fastest on a sample of these rays (best: none).
    TracePath calibrated = TracePath::best;
    /// The counted mode: when set, the scalar path's counting loop answers the query and adds what
    /// it did here (`path` is not read). Needs PathOffer::counts.
    TraceCounters* counters = nullptr;
};

/// What a structure offers, as built: the paths whose layouts exist, the queries each answers,
/// and the facts the path policy reads about it.
struct PathOffer {
    /// Per TracePath, one bit per Query it answers (0: the path is not offered). `best` stays 0.
    std::uint8_t queries[trace_path_count] = {};
    /// The counted mode (TraceRequest::counters) is available: the scalar layout was built.
    bool counts = false;
    /// Packets measured faster than single rays on coherent batches (the BVHs, and the kd-tree
    /// since its packet walk).
    bool packets_pay = false;
    /// Rays per packet of the packet path (the coherence measure's group size).
    std::uint32_t packet_lanes = 0;
    /// Diagonal of the scene's bounds (the coherence measure's scale).
    float scene_diagonal = 0.0f;
    /// A structure with SIMD paths whose layouts were not built (Layouts::scalar) says so here, so
    /// the policy can tell "not built" from "has none".
    bool simd_skipped = false;

    bool runs(TracePath p, Query q) const { return (queries[unsigned(p)] >> unsigned(q) & 1u) != 0; }
    bool has(TracePath p) const { return queries[unsigned(p)] != 0; }
    /// Offers `p` for every query kind there is.
    void add(TracePath p) { queries[unsigned(p)] = std::uint8_t((1u << query_count) - 1u); }
};

}  // namespace arbor::accel
