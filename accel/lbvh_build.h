#pragma once
/// `lbvh`: Morton codes of the centroids (quantized to the centroid bounds) -> parallel stable radix
/// sort of (code, index) -> binary radix tree over the sorted codes, collapsed into small leaves.
/// Lauterbach et al. 2009 "Fast BVH Construction on GPUs"; Karras 2012 for the hierarchy.
#include "accel/binary_bvh.h"
#include "accel/build_config.h"
#include "accel/prim_refs.h"
#include "accel/radix_tree.h"

namespace arbor::accel {

/// The LBVH variants compared in perf/lbvh_bench.cpp; the defaults are the measured winners.
struct LbvhOptions {
    RadixTreeMethod hierarchy = RadixTreeMethod::top_down;
    /// 30 (10 bits per axis; the code and the index share one 64-bit key) or 63 (21 per axis).
    int morton_bits = 63;
    /// Radix sort digit width: 8 or 11.
    int digit_bits = 8;
};

/// Wall time of each step, for the benchmark.
struct LbvhTimings {
    double codes_ms = 0, sort_ms = 0, hierarchy_ms = 0;
};

/// Builds the LBVH over `refs` with cfg.max_leaf_size (leaves hold at most that many primitives)
/// and cfg.parallel_threshold. Deterministic: the same tree for any thread count. All centroids
/// equal (identical codes) splits on the sorted position, so the depth stays within 64 + log2(n).
BinaryBvh build_lbvh(const PrimRefs& refs, const BuildConfig& cfg);
BinaryBvh build_lbvh(const PrimRefs& refs, const BuildConfig& cfg, const LbvhOptions& opt, LbvhTimings* timings = nullptr);

}  // namespace arbor::accel
