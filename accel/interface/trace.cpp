#include "accel/interface/trace.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

namespace arbor::accel {

RaceOutcome trace_parallel(const Accel& accel, std::span<const Ray> rays, std::span<Hit> hits, const TraceRequest& req,
                           std::size_t chunk) {
    const std::size_t n = std::min(rays.size(), hits.size()), c = std::max<std::size_t>(chunk, 1);
    const std::size_t chunks = (n + c - 1) / c;
    if (req.path == TracePath::best && !req.counters && race_chunk_count(chunks) != 0 &&
        race_settles(choose_path(accel.offer(), rays.first(n), req), accel.offer(), req))
        return race_chunks(chunks, race_chunk_count(chunks), [&](std::size_t k, TracePath path, ChunkPart part) {
            const std::size_t b = k * c, e = std::min(n, b + c);
            TraceRequest forced = req;
            forced.path = path;
            return trace_part(accel, rays.subspan(b, e - b), hits.subspan(b, e - b), forced, part);
        });
    tbb::enumerable_thread_specific<TraceCounters> counts;
    // Chunk k is rays [k*c, (k+1)*c): the boundaries do not depend on how TBB splits the range, so
    // rays of one image tile stay in one chunk (and in one packet) whatever the thread count.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, (n + c - 1) / c, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        TraceRequest local = req;
        if (req.counters) local.counters = &counts.local();
        for (std::size_t k = r.begin(); k != r.end(); ++k) {
            const std::size_t b = k * c, e = std::min(n, b + c);
            accel.trace(rays.subspan(b, e - b), hits.subspan(b, e - b), local);
        }
    });
    if (req.counters)
        for (const TraceCounters& t : counts) *req.counters += t;
    return {};
}

}  // namespace arbor::accel
