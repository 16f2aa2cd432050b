#pragma once
/// Tracing a whole batch of rays in parallel: TBB over fixed-size chunks, one Accel::trace call
/// (one virtual call) each. The result does not depend on the number of threads (every ray is
/// answered on its own).
#include "accel/interface/accel.h"
#include "accel/interface/path_race.h"

namespace arbor::accel {

/// Traces rays[i] into hits[i] for all i as `req` asks (Accel::trace), in chunks of `chunk` rays
/// run with tbb::parallel_for in the current task arena (limit threads with tbb::global_control or
/// a task_arena). Chunk k holds rays [k*chunk, (k+1)*chunk) whatever the thread count, so rays
/// written in tile order (engine/ray_gen.h: 64 rays per 8x8 tile) keep whole tiles together for
/// the packet paths. With `best`, each chunk is given its path by the policy, except a batch the
/// policy's measure cannot call (path_race.h: closest-hit rays that start together without sharing
/// an octant, at least 32 chunks), which is raced: the returned outcome says how (path `best`
/// when no race was run). Callers that report the path choose it once first
/// (interface/path_policy.h), as `arbor trace` does. In the counted mode (req.counters) the counts
/// of all chunks are summed into *req.counters.
RaceOutcome trace_parallel(const Accel& accel, std::span<const Ray> rays, std::span<Hit> hits, const TraceRequest& req,
                           std::size_t chunk = 1024);

/// The same for query `query` on `path`.
inline RaceOutcome trace_parallel(const Accel& accel, std::span<const Ray> rays, std::span<Hit> hits, Query query,
                                  TracePath path = TracePath::best, std::size_t chunk = 1024) {
    return trace_parallel(accel, rays, hits, TraceRequest{query, path}, chunk);
}

}  // namespace arbor::accel
