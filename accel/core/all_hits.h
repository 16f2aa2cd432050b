#pragma once
/// All hits along a ray: the sink a structure hands each ray's crossings to, and the one order
/// they are handed in (by t, then triangle number; each triangle once).
#include "accel/core/ray.h"

#include <algorithm>
#include <span>
#include <vector>

namespace arbor::accel {

/// Receives, ray by ray, the crossings of an Accel::trace_all batch.
class HitSink {
public:
    virtual ~HitSink() = default;
    /// Every triangle ray `i` of the batch crosses in [tnear, tfar], each once, sorted by t and then
    /// by triangle number (prim). The span lives for the call only; the sink may reorder it.
    virtual void take(std::size_t i, std::span<Hit> hits) = 0;
};

/// Sorts `hits` by (t, prim) and drops repeats of a triangle (a structure that reaches a triangle
/// more than once, the kd-tree, finds it with the same test and so at the same t: repeats are
/// neighbours after the sort).
inline void sort_unique_hits(std::vector<Hit>& hits) {
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.t < b.t || (a.t == b.t && a.prim < b.prim); });
    hits.erase(std::unique(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.prim == b.prim; }), hits.end());
}

}  // namespace arbor::accel
