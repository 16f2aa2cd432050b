#pragma once
/// `lbvh`: Morton codes of the centroids (quantized to the centroid bounds) -> parallel stable radix
/// sort of (code, index) -> binary radix tree over the sorted codes, collapsed into small leaves.
/// Lauterbach et al. 2009 "Fast BVH Construction on GPUs"; Karras 2012 for the hierarchy.
#include "accel/bvh/binary_bvh.h"
#include "accel/bvh/bvh_build_config.h"
#include "accel/bvh/build_prims.h"
#include "accel/bvh/prim_refs.h"
#include "accel/lbvh/radix_tree.h"

namespace arbor::accel {

/// How the Morton codes are made and sorted.
enum class MortonSort {
    /// 30-bit codes (10 bits per axis) packed with the reference index in one 64-bit key.
    bits30,
    /// 63-bit codes (21 per axis) sorted in full, the index carried as a value.
    bits63,
    /// The 63-bit order at about the 30-bit cost: sort the top 30 code bits packed with the index,
    /// then sort each run of equal top bits by the low 33 bits. Same order as bits63.
    bits63_refined,
};

/// The LBVH variants compared in perf/lbvh_bench.cpp; the defaults are the measured winners.
struct LbvhOptions {
    RadixTreeMethod hierarchy = RadixTreeMethod::top_down;
    MortonSort codes = MortonSort::bits63_refined;
    /// Radix sort digit width: 8 or 11.
    int digit_bits = 8;
    /// Leaves: every subtree of at most cfg.max_leaf_size triangles (false), or only those the SAH
    /// prefers to their split (true; radix_tree.h).
    bool sah_collapse = false;
};

/// Wall time of each step, for the benchmark.
struct LbvhTimings {
    double codes_ms = 0, sort_ms = 0, hierarchy_ms = 0;  ///< sort_ms includes the refinement
};

/// Builds the LBVH over `prims` with cfg.max_leaf_size (leaves hold at most that many primitives)
/// and cfg.parallel_threshold. Deterministic: the same tree for any thread count, and from
/// BuildPrims made from the triangles as from PrimRefs made from them. All centroids equal
/// (identical codes) splits on the sorted position, so the depth stays within 64 + log2(n).
BinaryBvh build_lbvh(const BuildPrims& prims, const BvhBuildConfig& cfg, const LbvhOptions& opt, LbvhTimings* timings = nullptr);
/// The default options; the input is freed on return (the signature of the other builders).
BinaryBvh build_lbvh(BuildPrims&& prims, const BvhBuildConfig& cfg);
BinaryBvh build_lbvh(const PrimRefs& refs, const BvhBuildConfig& cfg);
BinaryBvh build_lbvh(const PrimRefs& refs, const BvhBuildConfig& cfg, const LbvhOptions& opt, LbvhTimings* timings = nullptr);

}  // namespace arbor::accel
