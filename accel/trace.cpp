#include "accel/trace.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace arbor::accel {

void trace_parallel(const Accel& accel, std::span<const Ray> rays, std::span<Hit> hits, Query query,
                    TracePath path, std::size_t chunk) {
    const std::size_t n = std::min(rays.size(), hits.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, std::max<std::size_t>(chunk, 1)),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          const auto in = rays.subspan(r.begin(), r.size());
                          const auto out = hits.subspan(r.begin(), r.size());
                          if (query == Query::closest) accel.intersect(in, out, path);
                          else accel.occluded(in, out, path);
                      });
}

}  // namespace arbor::accel
