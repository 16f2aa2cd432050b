#pragma once
/// Seams: where instances can meet. A ray through an edge shared by two triangles of one mesh is
/// decided once by the watertight test; an edge shared by two instances is an open edge of each
/// mesh (used by one triangle of it), and each instance tests the ray in its own object space,
/// rounded its own way, so both may miss. The triangles around the open edges (every triangle
/// touching a vertex of an open edge: the fans that a ray through a boundary vertex meets) are
/// therefore also placed in world space, per instance, with their corners carried over in double
/// and rounded to float as a flattened scene rounds them, and tested there with the caller's own
/// ray: two instances whose seams meet in the same float corners are watertight against each
/// other as two triangles of one mesh are.
#include "accel/core/geometry.h"

#include <cstdint>
#include <vector>

namespace arbor::accel {

/// A mesh's seam triangles, found by exact corner positions (so unwelded copies of a vertex count
/// as one): triangle numbers in ascending order, and a flag per triangle.
struct SeamSet {
    std::vector<std::uint32_t> tris;
    std::vector<std::uint8_t> flag;  ///< 1 for a seam triangle, per triangle of the mesh
};

/// The seam triangles of `mesh` (open edges: used by exactly one finite, non-degenerate triangle).
SeamSet find_seams(const TriangleView& mesh);

}  // namespace arbor::accel
