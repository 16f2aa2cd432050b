#pragma once
/// Independent checks of a built kd-tree (tests only): structure, the reference invariant against a
/// brute-force triangle/box overlap test, and the ropes against point queries.
#include "accel/kdtree/kdtree_node.h"
#include "engine/mesh.h"

#include <string>
#include <vector>

namespace arbor::testing {

using accel::Vec3f;

/// Box of every node, from the scene box and the splits.
std::vector<accel::Bounds> kd_node_boxes(const accel::KdTree& tree);
/// One past the last node of every node's subtree (subtrees are contiguous in depth-first order).
std::vector<std::uint32_t> kd_subtree_ends(const accel::KdTree& tree);
/// The leaf node holding point p (points on a split plane go right).
std::uint32_t kd_locate(const accel::KdTree& tree, const Vec3f& p);

/// True when triangle (a, b, c) meets the open box (separating-axis test in double; a triangle
/// that only touches the box's boundary, or is within a rounding margin of it, counts as outside).
bool triangle_meets_open_box(const Vec3f& a, const Vec3f& b, const Vec3f& c, const accel::Bounds& box);

/// Structure: indices in range, every leaf reached once, splits strictly inside their node box,
/// leaf boxes equal to the boxes implied by the splits, depth within the limit, refs in range and
/// ascending in prim order per leaf, every finite triangle stored once and no other.
std::string check_kdtree_structure(const accel::KdTree& tree, const accel::TriangleView& tris);
/// References: every finite triangle is referenced by every leaf whose open box it meets, and for
/// each of its corners by some leaf whose closed box holds that corner (flat triangles lying in a
/// split plane go to one side but are never lost); the bounds of every referenced triangle meet
/// the leaf's closed box.
/// O(leaves * triangles): small meshes only.
std::string check_kdtree_refs(const accel::KdTree& tree, const accel::TriangleView& tris);
/// Ropes: a face on the scene box has no rope; otherwise the rope's node lies beyond the face, holds
/// the whole face, and is a leaf or is cut by its split inside the face (the smallest such node);
/// points just outside the face are located inside the rope's subtree.
std::string check_kdtree_ropes(const accel::KdTree& tree);

/// Small test meshes.
engine::Mesh random_soup(std::size_t n, float size, std::uint32_t seed);
/// Flat axis-aligned grid in the plane z = 0 with integer vertices (0..n, 0..n), two triangles per cell.
engine::Mesh integer_grid(int n);
/// Unit cubes at integer positions (x + y + z even) in [0, n)^3: every face in an integer plane.
engine::Mesh integer_cubes(int n);

}  // namespace arbor::testing
