#pragma once
/// The kd-tree's partition as a binary BVH, for the BVHs' SIMD machinery (wide/): "kd cells as
/// wide nodes". A kd-tree's leaves are disjoint axis-aligned cells that tile the scene box; as a
/// BinaryBvh an interior kd node is a node whose box is its CELL (the scene box cut by its
/// ancestors' planes), a non-empty kd leaf a leaf with its triangles (a triangle that spans
/// several cells is listed in each), and EMPTY leaves are left out (a node with one empty child is
/// replaced by its other child, an all-empty subtree disappears): the empty space a rope walk
/// steps through costs nothing. The SAH collapse (make_wide_layout) then makes N-wide nodes of it,
/// traced by the BVHs' single-ray and packet walks unchanged (KdCellAccel, kdtree_cells.cpp).
///
/// Closest hit stays exact: the exact hit point lies in a cell whose leaf lists the triangle
/// (kdtree_clip.h is conservative), and the padded slab test is conservative for that cell as for
/// a BVH box. Not a valid BinaryBvh in validate_bvh's sense (triangles repeat across leaves).
#include "accel/bvh/binary_bvh.h"
#include "accel/structures/kdtree_accel.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace arbor::accel {

/// The cell tree of `tree`: pre-order, siblings adjacent, children after parents; leaves hold the
/// kd leaves' prims (original numbers) in the leaf's ascending prim order. No node (empty) when
/// the tree has no non-empty leaf. `tight`: each leaf's box is its cell cut to its triangles'
/// bounds, each interior box the union of its children's (a step towards a spatial-split BVH;
/// KdWalk::tight_cells).
BinaryBvh kd_cell_bvh(const KdTree& tree, bool tight = false);

/// The kd-tree's triangles as a TriangleView indexed by their original prim numbers (the view the
/// collapse reads corners from; prims the tree dropped point at corner 0, never referenced).
struct KdPrimView {
    std::vector<float> x, y, z;
    std::vector<std::uint32_t> indices;
    TriangleView view() const { return {x, y, z, indices}; }
};
KdPrimView kd_prim_view(const KdTree& tree);

/// The cell tree's SIMD paths, made by the caller (the factory, through the kernel set in use):
/// an Accel over `cells` and `prims` with the SIMD layout only, and the width of its nodes.
struct KdCellPaths {
    std::function<std::unique_ptr<Accel>(const BinaryBvh& cells, const TriangleView& prims, const BuildConfig& cfg)> make;
    std::uint32_t width = 0;
};

/// The kd-tree with its cell paths (cfg.kd_blocks.walk cells or tight_cells): `single` and `packet`
/// trace the cell tree's N-wide layout made by `paths` with the BVHs' walks (structures/wide_paths.h),
/// the scalar path stays the rope walk.
std::unique_ptr<KdTreeAccel> make_kd_cell_accel(KdTree tree, const BuildConfig& cfg, double build_ms,
                                                const KdCellPaths& paths);

}  // namespace arbor::accel
