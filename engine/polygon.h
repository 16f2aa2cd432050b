#pragma once
/// Polygons to triangles, as spec/rayfile.md numbers them: a convex polygon of k corners is fanned
/// from its first corner, (0,1,2), (0,2,3), ... (0,k-2,k-1); a polygon that is not convex (fanning
/// would cover area outside it, e.g. an L, a star or a ring joined by a bridge) is cut into k-2
/// triangles by ear clipping (Meisters 1975) in the plane that its Newell normal is most
/// perpendicular to. Each triangle keeps the polygon's winding.
#include "accel/core/geometry.h"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace arbor::engine {

using accel::Vec3f;

/// Triangles of the polygon with corners `corners` (in order), as triples of corner positions
/// 0..k-1, appended to `out` (k - 2 of them for k >= 3, none otherwise).
void triangulate_polygon(std::span<const Vec3f> corners, std::vector<std::array<std::uint32_t, 3>>& out);

/// True when fanning the polygon from its first corner is right: the polygon, projected on the
/// plane of its Newell normal, turns one way only (collinear corners allowed) and winds once.
/// Polygons with a zero Newell normal (all corners on a line, or non-finite) count as convex.
bool polygon_is_convex(std::span<const Vec3f> corners);

}  // namespace arbor::engine
