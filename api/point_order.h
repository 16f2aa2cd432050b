#pragma once
/// The order a point query visits its points in: along a Morton curve over the points' box, so
/// that consecutive points lie near each other. Each search then starts from its neighbour's
/// answer (accel::warm_reach) with the nodes it needs still in cache; the answers do not depend on
/// the order (every search returns the same record from any start: accel/core/closest_point.h).
#include "api/batch.h"

#include <cstdint>
#include <vector>

namespace arbor {

/// Point indices in curve order (non-finite points last, in their given order); empty = the given
/// order, for batches too small to gain from it. Sorted in `arena`.
std::vector<std::uint32_t> spatial_order(const PointArrays& p, CallArena& arena);

}  // namespace arbor
