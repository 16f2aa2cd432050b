#pragma once
/// The SAH kd-tree builder: a pure function from triangles and settings to a KdTree with ropes.
#include "accel/core/build_config.h"
#include "accel/kdtree/kdtree_node.h"

namespace arbor::accel {

/// Depth limit of the kd-tree for n triangles: 8 + 1.3 log2(n), at most kd_max_depth.
std::uint32_t kd_depth_limit(std::size_t n);

/// Builds the SAH kd-tree of the finite triangles of `tris` (Wald & Havran 2006: one event sort at
/// the root, then an O(N) sweep and split per node) with the empty-space factor, depth limit and
/// perfect-split option of `cfg`, then its ropes (kdtree_ropes.h). Non-finite triangles are dropped
/// and counted. Deterministic: the same tree, bit for bit, for any number of TBB threads (children
/// are built in parallel above cfg.parallel_threshold triangles and laid out depth-first after).
/// Exact float comparisons run under IeeeFpGuard, so the caller's FTZ/DAZ mode does not matter.
/// Throws std::length_error when the build's temporaries would exceed cfg.max_memory (0: no limit).
KdTree build_kdtree(const TriangleView& tris, const BuildConfig& cfg = {});

/// Statistics of a built tree (SAH cost normalized to the scene box area: sum over interior nodes
/// of K_T * area + over leaves of K_I * area * count, divided by the root area).
struct KdTreeStats {
    std::size_t nodes = 0, leaves = 0, empty_leaves = 0, refs = 0;
    std::uint32_t max_depth = 0, max_leaf_size = 0;
    double mean_leaf_depth = 0.0;
    double sah_cost = 0.0;
};
KdTreeStats kd_tree_stats(const KdTree& tree, float traversal_cost = 1.0f, float intersection_cost = 1.0f);

}  // namespace arbor::accel
