#pragma once
/// Triangle strips to triangles, as PLY's `tristrips` element stores them (Greg Turk's PLY: a list
/// `vertex_indices` per record, -1 ends a strip and starts the next).
#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace arbor::engine::formats {

/// What one strip list gave.
struct StripCounts {
    std::uint64_t triangles = 0;   ///< appended to `out`
    std::uint64_t degenerate = 0;  ///< dropped: two of their indices are equal (strip joints)
};

/// Appends the triangles of `indices` to `out`. Within a strip (from the list's start or a -1 to
/// the next -1 or the end) the k-th window of three indices (a, b, c), k = 0, 1, ..., is the
/// triangle (a, b, c) for even k and (b, a, c) for odd k, so every triangle keeps the first one's
/// orientation. A window with a repeated index is a joint between stitched strips and is dropped,
/// but still counts for k, as the winding alternates over it. Indices other than -1 are passed
/// through unchecked (the caller checks them against the vertex list); a strip of fewer than
/// three indices gives nothing.
StripCounts strip_triangles(std::span<const std::int64_t> indices, std::vector<std::array<std::int64_t, 3>>& out);

}  // namespace arbor::engine::formats
