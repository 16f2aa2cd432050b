#pragma once
/// BvhBuildConfig: the settings the binary BVH builders read (bvh-median, bvh-sah and its sweep
/// reference, lbvh; bvh_build.h, lbvh/lbvh_build.h), and nothing else. Part of BuildConfig
/// (accel/interface/build_config.h) as `bvh`.
#include <cstdint>

namespace arbor::accel {

struct BvhBuildConfig {
    /// Maximum triangles per leaf (bvh-median splits down to this; SAH and LBVH use it as the cap).
    /// The seed report used 1. `--leaf-size`.
    std::uint32_t max_leaf_size = 4;
    /// Ranges of at most this many triangles become one leaf, unsplit (0 or 1: no floor; a leaf may
    /// then hold more than max_leaf_size). Derived, not set: build_bvh_accel (bvh_accel.h) puts
    /// bvh_leaf_floor() here for the builders, from simd_leaf_floor below.
    std::uint32_t leaf_floor = 0;
    /// The top-down builders' (bvh-median, bvh-sah) limit on their own peak, in bytes (0: none):
    /// the build primitives and ids are counted when it starts, the nodes as they are made, and
    /// the build throws MemoryLimitError as soon as the count passes it, before the tree's
    /// nodes are placed (bvh_top_down.h). Derived, not set: build_bvh_accel puts
    /// BuildConfig::max_memory here.
    std::uint64_t max_bytes = 0;
    /// Builds of the SIMD layouts only (BuildConfig::layouts == simd): the leaf_floor they get. 0 =
    /// the SIMD layout's width N (a leaf of the N-wide layout is a run of N-triangle blocks that the
    /// collapse fills from whole binary subtrees anyway, so splitting below N triangles mostly costs
    /// build time), 1 = none (the binary tree of the scalar build), else that many triangles.
    /// Measured by scripts/bench_leaf_floor.sh. `--simd-leaf-floor`.
    std::uint32_t simd_leaf_floor = 0;
    /// Binned SAH: bins per axis (16..32 is the useful range) for big ranges; a range of n < 20 x
    /// (bins - 4) primitives gets 4 + n/20 (Embree's rule: fewer bins where clearing and sweeping
    /// them would cost more than binning). `--sah-bins`.
    std::uint32_t sah_bins = 16;
    /// Binned SAH: from this depth on only median splits are made (each halves its range, so the
    /// tree stays shallower than sah_depth_limit + 32 whatever the input).
    std::uint32_t sah_depth_limit = 48;
    /// SAH costs, relative: traversal step vs one ray/triangle test (also the costs of the SAH cost
    /// a BVH build reports, BuildStats::sah_cost).
    float traversal_cost = 1.0f;
    float intersection_cost = 1.0f;
    /// Below this many primitives a recursive build runs serially (bvh v2 and Embree use 1024).
    std::uint32_t parallel_threshold = 1024;
};

}  // namespace arbor::accel
