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

/// Visiting position k's point number in `order` (spatial_order's answer; empty: k itself).
inline std::size_t point_at(const std::vector<std::uint32_t>& order, std::size_t k) {
    return order.empty() ? k : std::size_t(order[k]);
}

/// The points visited at positions begin .. end - 1 of `order`, in this thread's buffer.
inline std::span<const accel::Vec3f> load_points(const PointArrays& p, const std::vector<std::uint32_t>& order,
                                                 std::size_t begin, std::size_t end) {
    if (order.empty()) return load_points(p, begin, end);
    thread_local std::vector<accel::Vec3f> buf;
    buf.resize(end - begin);
    for (std::size_t k = begin; k < end; ++k) buf[k - begin] = read_vec3(p.xyz, p.stride, order[k]);
    return buf;
}

}  // namespace arbor
