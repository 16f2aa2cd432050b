#pragma once
/// Build settings shared by all structures. Every field has a documented default; there are no
/// global knobs.
#include <cstdint>

namespace arbor::accel {

/// Which traversal layouts a structure builds: `all` (every path can be traced: tests, benchmarks),
/// `scalar` (only the reference path's layout) or `simd` (only the layouts of the SIMD paths
/// `single` and `packet`, which `best` takes). A path whose layout was not built is traced on one
/// that was (Accel::offer says which exist; every path gives the same answers).
enum class Layouts : std::uint8_t { all, scalar, simd };

struct BuildConfig {
    /// Maximum triangles per BVH leaf (bvh-median splits down to this; SAH and LBVH use it as the
    /// cap). The seed report used 1.
    std::uint32_t max_leaf_size = 4;
    /// BVHs: ranges of at most this many triangles become one leaf, unsplit (0 or 1: no floor; a
    /// leaf may then hold more than max_leaf_size). build_bvh_accel sets it for builds of the SIMD
    /// layouts only (see simd_leaf_floor); the builders read it, nobody else needs to.
    std::uint32_t leaf_floor = 0;
    /// BVHs, builds of the SIMD layouts only (layouts == simd): the leaf_floor they get. 0 = the
    /// SIMD layout's width N (a leaf of the N-wide layout is a run of N-triangle blocks that the
    /// collapse fills from whole binary subtrees anyway, so splitting below N triangles mostly costs
    /// build time), 1 = none (the binary tree of the scalar build), else that many triangles.
    /// Measured in perf/results/leaf-floor-2026-12-01.md.
    std::uint32_t simd_leaf_floor = 0;
    /// Binned SAH: bins per axis (16..32 is the useful range) for big ranges; a range of n < 20 x
    /// (bins - 4) primitives gets 4 + n/20 (Embree's rule: fewer bins where clearing and sweeping them
    /// would cost more than binning).
    std::uint32_t sah_bins = 16;
    /// Binned SAH: from this depth on only median splits are made (each halves its range, so the
    /// tree stays shallower than sah_depth_limit + 32 whatever the input).
    std::uint32_t sah_depth_limit = 48;
    /// SAH costs, relative: traversal step vs one ray/triangle test.
    float traversal_cost = 1.0f;
    float intersection_cost = 1.0f;
    /// Below this many primitives a recursive build runs serially (bvh v2 and Embree use 1024).
    std::uint32_t parallel_threshold = 1024;
    /// kd-tree: SAH cost of a traversal step (K_T) against intersection_cost (K_I). The rope walk
    /// pays per leaf (exit planes, rope, descent, a cache miss), so the kd-tree wants bigger leaves
    /// than the BVH ratio gives: on the bunny 1 -> 4 cuts nodes 6x and build time 2.5x at the same
    /// trace speed (perf/kdtree_bench). The reported SAH cost still uses traversal_cost.
    float kd_traversal_cost = 4.0f;
    /// kd-tree: nodes with more triangles than this choose their plane from 256 bins per axis
    /// (no events, O(N)); smaller ones by Wald-Havran's exact event sweep, their events sorted once
    /// when they drop below. 0xFFFFFFFF: exact sweep from the root (the pure O(N log N) build).
    std::uint32_t kd_exact_below = 4096;
    /// kd-tree: clip triangles to the node box when computing split candidates (perfect splits).
    bool kd_perfect_splits = true;
    /// kd-tree: factor on the SAH cost of a split that cuts off empty space (one side holds no
    /// triangle); Wald & Havran's lambda = 0.8, i.e. such splits look 20% cheaper. 1 = no bonus.
    float kd_empty_bonus = 0.8f;
    /// BVHs: children per node of the SIMD traversal layout (4, 8 or 16; 0 = the measured best of
    /// this build, see accel/wide/wide_paths.h). A width the build's ISA lacks falls back to the default.
    std::uint32_t bvh_width = 0;
    /// BVHs: a binary subtree with at most this many triangles becomes one leaf of the SIMD layout
    /// (0 = the width).
    std::uint32_t wide_merge = 0;
    /// kd-tree, SIMD paths: triangles per SIMD block of a leaf, 8 or 16 (0 = the measured best,
    /// accel/kdtree/kdtree_simd.h; 16 needs AVX-512, else 8 is used).
    std::uint32_t kd_block_width = 0;
    /// BVHs and kd-tree, packet path: rays per packet, 8 or 16 (0 = 16 with AVX-512, else 8).
    std::uint32_t packet_lanes = 0;
    /// BVHs, packet path: at a node reached by at most this many lanes they go on as single rays
    /// (kd-tree: a leaf reached by at most this many lanes is tested lane by lane) (-1 = lanes / 8).
    int packet_switch = -1;
    /// BVHs, packet path: the same for packets whose lanes do not all share a direction octant
    /// (diffuse bounces) (-1 = lanes / 2).
    int packet_switch_mixed = -1;
    /// Upper bound on build memory in bytes (0 = no limit); a build that would exceed it throws
    /// MemoryLimitError (memory_estimate.h): checked from the triangle count before building, by the
    /// kd-tree builder as it grows, and against the measured peak afterwards.
    std::uint64_t max_memory = 0;
    /// Traversal layouts to build (BVHs: the two-box scalar layout and/or the N-wide SIMD layout;
    /// kd-tree: its SIMD leaf blocks or not). The command line builds only what the requested path
    /// reads.
    Layouts layouts = Layouts::all;
};

}  // namespace arbor::accel
