#pragma once
/// Building the structures of one benchmark scene, timed at each thread count, and the traced
/// configurations (structure x path, Embree mode x call) they offer.
#include "accel/interface/trace.h"
#include "perf/bench_options.h"

#include <map>
#include <memory>
#include <string>
#include <vector>

#ifdef ARBOR_HAVE_EMBREE
#include "perf/embree_peer.h"
#endif

namespace arbor::perf {

class EmbreePeer;

/// One structure of a scene: an arbor Accel or an Embree peer, with its build times.
struct Built {
    std::string name;                       ///< "bvh-sah", "embree", "embree-high", ...
    std::unique_ptr<accel::Accel> accel;    ///< set for arbor structures
#ifdef ARBOR_HAVE_EMBREE
    EmbreeConfig embree_cfg;
    std::unique_ptr<EmbreePeer> peer;       ///< set for Embree modes
#endif
    std::map<int, std::vector<double>> build_ms;  ///< wall ms of each build, by thread count
    bool embree = false;                    ///< an Embree mode (else an arbor structure)
    bool unavailable = false;               ///< make_accel said "not available"

    bool is_embree() const { return embree; }
    std::size_t memory_bytes() const;
};

/// A traced configuration: a structure and the way rays go through it.
struct TraceConfig {
    const Built* built = nullptr;
    std::string path;                      ///< scalar|packet|single or 1|8|16|1M
    accel::TracePath arbor_path = accel::TracePath::scalar;
    int embree_call = 0;                   ///< EmbreeCall when built->is_embree()

    /// Traces all rays in parallel (TBB chunks) with the current thread limit.
    void trace(std::span<const accel::Ray> rays, std::span<accel::Hit> hits, accel::Query q, bool coherent) const;
};

/// Names of the structures of `o` that are arbor's (validated: throws InputError naming
/// --structures for an unknown one, or for "auto").
std::vector<accel::AccelKind> bench_structures(const BenchOptions& o);

/// The largest build measured so far per structure (triangles, ms at all threads), to skip builds
/// predicted to take longer than BenchOptions::max_build_seconds on bigger scenes.
using BuildHistory = std::map<std::string, std::pair<std::size_t, double>>;

/// Builds every structure of `o` (and the Embree modes when built) over `tris`, `repeats` times at
/// each thread count of `threads` (interleaved: every structure once, then again). Structures that
/// make_accel cannot build, or whose single build `history` predicts (N log N from the largest
/// earlier build) to exceed o.max_build_seconds, are left out and reported in `notes`.
std::vector<Built> build_structures(const accel::TriangleView& tris, const BenchOptions& o,
                                    const std::vector<int>& threads, int repeats, std::vector<std::string>& notes,
                                    BuildHistory& history);

/// The configurations to trace: every path each arbor structure has (Accel::offer: scalar first),
/// and for Embree the default mode with every call, the other modes with rtcIntersect1 and 1M
/// (Embree 3 only: perf::embree_calls()).
std::vector<TraceConfig> trace_configs(const std::vector<Built>& built);

}  // namespace arbor::perf
