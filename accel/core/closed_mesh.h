#pragma once
/// Whether a triangle mesh is closed: every edge shared by exactly two triangles.
#include <cstdint>
#include <span>

namespace arbor::accel {

/// True when every undirected edge {a, b} of the triangles (index triples) is used by exactly two
/// of them. Edges are compared by vertex number: vertices are not welded, so two vertices at the
/// same position are different vertices (a mesh whose triangles do not share vertex numbers, as an
/// STL file's, is open). Orientation is not checked (two triangles may use an edge in the same
/// direction). A triangle with a repeated vertex has an edge {a, a} that no other triangle closes
/// with it unless one more does. No triangles: true (nothing is open). Parallel sort of the edges;
/// the answer does not depend on the thread count.
bool is_closed_mesh(std::span<const std::uint32_t> indices);

}  // namespace arbor::accel
