#pragma once
/// The kd-tree's settings, each read by one part of it: KdBuildConfig by the builder
/// (kdtree_build.h), KdBlockConfig by the SIMD leaf blocks (kdtree_simd.h). Parts of BuildConfig
/// (accel/interface/build_config.h) as `kd` and `kd_blocks`.
#include <cstdint>

namespace arbor::accel {

struct KdBuildConfig {
    /// SAH cost of a traversal step (K_T) against intersection_cost (K_I). Every walk pays per
    /// leaf (rope or pop, exit planes or intervals in double, a cache miss) and tests a leaf's
    /// triangles as one SIMD block, so the kd-tree wants bigger leaves than the BVH ratio gives: on
    /// the bunny 1 -> 4 cut nodes 6x and build time 2.5x at the same trace speed (`arbor-bench kdtree`);
    /// with the packet walk 4 -> 12 ran 1.10-1.14x (median per kind, min 0.97x) on the held-out rays,
    /// 2 and 1.5 slower.
    float traversal_cost = 12.0f;
    float intersection_cost = 1.0f;
    /// K_T of the SAH cost the build reports (BuildStats::sah_cost): 1, the BVHs' default, so that
    /// the reported figures compare across structures.
    float reported_traversal_cost = 1.0f;
    /// Nodes with more triangles than this choose their plane from 256 bins per axis (no events,
    /// O(N)); smaller ones by Wald-Havran's exact event sweep, their events sorted once when they
    /// drop below. 0xFFFFFFFF: exact sweep from the root (the pure O(N log N) build).
    std::uint32_t exact_below = 4096;
    /// Clip triangles to the node box when computing split candidates (perfect splits).
    bool perfect_splits = true;
    /// Factor on the SAH cost of a split that cuts off empty space (one side holds no triangle);
    /// Wald & Havran's lambda = 0.8, i.e. such splits look 20% cheaper. 1 = no bonus.
    float empty_bonus = 0.8f;
    /// Below this many triangles a node's subtree is built serially.
    std::uint32_t parallel_threshold = 1024;
};

/// Which layout the kd-tree's SIMD paths (`single`, `packet`) trace. `ropes`: the kd nodes with
/// the leaves' triangles in SIMD blocks (kdtree_simd.h: the rope walk, the stack walk and its packet
/// form, leaf for leaf the scalar path's). `cells`: the kd partition as a binary BVH of its
/// non-empty cells, collapsed to N-wide nodes and traced by the BVHs' walks (kdtree_cells.h).
/// `tight_cells`: the same with each cell's box cut to its triangles' bounds (a step from the kd
/// partition towards a spatial-split BVH); the default, measured fastest
/// on the held-out rays.
enum class KdWalk : std::uint8_t { ropes, cells, tight_cells };
/// "ropes", "cells", "tight-cells" (`--kd-walk`).
inline const char* kd_walk_name(KdWalk w) {
    return w == KdWalk::ropes ? "ropes" : w == KdWalk::cells ? "cells" : "tight-cells";
}

/// The SIMD paths' layout.
struct KdBlockConfig {
    /// The walk of the SIMD paths (`--kd-walk`).
    KdWalk walk = KdWalk::tight_cells;
    /// ropes: triangles per SIMD block of a leaf, 8 or 16 (0 = the measured best, kdtree_simd.h; 16 needs
    /// AVX-512, else 8 is used).
    std::uint32_t width = 0;
};

}  // namespace arbor::accel
