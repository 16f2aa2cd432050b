#pragma once
/// Ropes of the kd-tree's leaves. See "Stackless KD-Tree Traversal for High Performance GPU Ray
/// Tracing", S. Popov, J. Günther, H.-P. Seidel, P. Slusallek, 2007 (§3.1 and the rope optimization).
#include "accel/kdtree/kdtree_node.h"

namespace arbor::accel {

/// Sets the six ropes of every leaf of `tree`: for each face, the smallest node whose box contains
/// the whole face on its outer side (a leaf, or an interior node whose split plane cuts the face),
/// or kd_no_rope when the face lies on the scene box. Ropes are passed down from the root, each
/// child's ropes pushed down ("optimized") against the child's box.
void compute_ropes(KdTree& tree);

/// The node reached by pushing `rope` down against a box whose `face` is being roped: while the
/// node is interior and its split does not cut the face, go to the child on the face's side.
std::uint32_t push_rope_down(const KdTree& tree, std::uint32_t rope, int face, const Bounds& box);

}  // namespace arbor::accel
