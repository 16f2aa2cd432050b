#pragma once
/// Smooth vertex normals for meshes whose file has none (`arbor render --smooth`): at every corner
/// without a normal, the angle-weighted mean (Thürmer & Wüthrich 1998) of the geometric normals of
/// the triangles around that corner's position, taking only triangles within `crease_degrees` of
/// the corner's own triangle, so hard edges (a box's, a mechanical part's) stay sharp. Corners are
/// joined by position (bit-equal coordinates), so files that repeat vertices per triangle (STL)
/// are smoothed too. Corners that share a position and see the same triangles share one normal.
#include "engine/mesh.h"

namespace arbor::engine {

/// Fills the normals of corners that have none; returns how many corners got one.
std::size_t compute_smooth_normals(Mesh& mesh, float crease_degrees = 60.0f);

}  // namespace arbor::engine
