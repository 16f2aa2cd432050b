#pragma once
/// Winding numbers on the scalar two-box layout (Bvh2Layout): the adapter winding_walk.h reads, the
/// tree over a BVH's own layout, and an internal tree for the structures whose own partition
/// cannot be summed over (the kd-tree lists a triangle in every leaf it crosses).
#include "accel/bvh/bvh2_layout.h"
#include "accel/core/winding_tree.h"

#include <memory>

namespace arbor::accel {

/// A winding tree over `layout` (which must outlive it): one dipole per child of every node,
/// computed here.
std::unique_ptr<WindingTree> make_bvh2_winding(const Bvh2Layout& layout);

/// A winding tree that owns its BVH: a binned-SAH binary BVH over the finite triangles of `tris`
/// (leaves of up to 4), converted to the scalar layout, with its dipoles. The layout copies the
/// triangles, so `tris` need not outlive the tree.
std::unique_ptr<WindingTree> make_internal_winding(const TriangleView& tris);

}  // namespace arbor::accel
