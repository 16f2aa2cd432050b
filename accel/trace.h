#pragma once
/// Tracing a whole batch of rays in parallel: TBB over fixed-size chunks, one virtual call each.
/// The result does not depend on the number of threads (every ray is answered on its own).
#include "accel/accel.h"

namespace arbor::accel {

enum class Query { closest, any };

/// Traces rays[i] into hits[i] for all i, in chunks of `chunk` rays run with tbb::parallel_for
/// in the current task arena (limit threads with tbb::global_control or a task_arena). Chunk k
/// holds rays [k*chunk, (k+1)*chunk) whatever the thread count, so rays written in tile order
/// (engine/ray_gen.h: 64 rays per 8x8 tile) keep whole tiles together for the packet paths.
void trace_parallel(const Accel& accel, std::span<const Ray> rays, std::span<Hit> hits, Query query,
                    TracePath path = TracePath::best, std::size_t chunk = 1024);

}  // namespace arbor::accel
