#pragma once
/// BinaryBvh: the one canonical tree every BVH builder (bvh-median, bvh-sah, lbvh) produces.
/// Simple AoS, 32-byte nodes; traversal layouts are converted from it on purpose (bvh_layout.h).
#include "accel/core/geometry.h"

#include <cstdint>
#include <string>
#include <vector>

namespace arbor::accel {

/// 32 bytes. Interior node: count == 0, children at nodes[first] and nodes[first + 1] (siblings
/// are always adjacent). Leaf: count > 0 primitives, prim_ids[first .. first + count).
struct BvhBuildNode {
    Bounds box;
    std::uint32_t first = 0;
    std::uint32_t count = 0;

    bool is_leaf() const { return count != 0; }
};
static_assert(sizeof(BvhBuildNode) == 32);

struct BinaryBvh {
    std::vector<BvhBuildNode> nodes;     ///< nodes[0] is the root (a leaf when the scene is tiny)
    std::vector<std::uint32_t> prim_ids; ///< triangle numbers in leaf order; each finite triangle once
    std::size_t dropped_nonfinite = 0;   ///< triangles left out because a corner is NaN/Inf
    std::size_t build_peak_bytes = 0;    ///< largest temporary memory the builder used

    bool empty() const { return prim_ids.empty(); }
};

/// Statistics of a valid binary tree (every node reachable, children after parents): nodes, leaves, depths, SAH cost normalized to the root area
/// (cost = sum over interior nodes of area * traversal_cost + sum over leaves of area * count *
/// intersection_cost, divided by the root area).
struct BvhTreeStats {
    std::size_t nodes = 0, leaves = 0;
    std::uint32_t max_depth = 0;
    double mean_leaf_depth = 0.0;
    double sah_cost = 0.0;
    std::uint32_t max_leaf_size = 0;
};
BvhTreeStats bvh_tree_stats(const BinaryBvh& bvh, float traversal_cost = 1.0f, float intersection_cost = 1.0f);

/// Checks the structural invariants against the triangles: every finite triangle referenced exactly
/// once, no non-finite one referenced, every node box contains its children's boxes (interior) or
/// its triangles' boxes (leaf), child indices in range and acyclic, leaves no larger than
/// max_leaf_size (0 = no limit). Returns an empty string when valid, else the first violation.
std::string validate_bvh(const BinaryBvh& bvh, const TriangleView& tris, std::uint32_t max_leaf_size = 0);

}  // namespace arbor::accel
