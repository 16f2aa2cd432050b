#pragma once
/// The top-down BVH builders: pure functions of the build prims (or prim refs) and the config
/// (bvh_top_down.h is their shared frame). Each returns a BinaryBvh whose leaves hold at most
/// cfg.max_leaf_size triangles; the result is bit-identical for any number of threads, and the
/// same from BuildPrims made from the triangles as from PrimRefs made from them (build_prims.h).
/// The BuildPrims overloads consume their input (it is partitioned in place).
#include "accel/bvh/binary_bvh.h"
#include "accel/bvh/bvh_build_config.h"
#include "accel/bvh/build_prims.h"
#include "accel/bvh/prim_refs.h"

namespace arbor::accel {

/// `bvh-median`: object median of the centroids on the longest axis of the centroid bounds
/// (std::nth_element), down to cfg.max_leaf_size. All centroids equal: split at the index median.
BinaryBvh build_bvh_median(const PrimRefs& refs, const BvhBuildConfig& cfg);
BinaryBvh build_bvh_median(BuildPrims&& prims, const BvhBuildConfig& cfg);

/// `bvh-sah`: binned SAH, I. Wald, "On fast Construction of SAH-based Bounding Volume
/// Hierarchies", RT 2007: cfg.sah_bins (2..32) bins per axis over the centroid bounds, a leaf where
/// the SAH says so and the range fits in cfg.max_leaf_size, parallel binning on large ranges. The
/// bins keep their primitives' boxes and centroid boxes (sah_bin_box.h), so both sides' bounds come
/// from the bins and the partition only moves primitives.
/// Ranges of at most 16 primitives are split by an exact SAH sweep over their centroids sorted on
/// the longest axis of the centroid bounds instead (cheaper than binning them).
/// Degenerate centroid bounds, or a binning that cannot separate the range, fall back to a median
/// split; from depth cfg.sah_depth_limit on only median splits are made, so the depth stays under
/// that limit + 32.
BinaryBvh build_bvh_sah(const PrimRefs& refs, const BvhBuildConfig& cfg);
BinaryBvh build_bvh_sah(BuildPrims&& prims, const BvhBuildConfig& cfg);

/// Full-sweep SAH (every split position between sorted centroids on all three axes), the quality
/// reference of bvh-sah. O(N log^2 N) and serial per node: for tests and benchmarks, not registered
/// as a structure.
BinaryBvh build_bvh_sah_sweep(const PrimRefs& refs, const BvhBuildConfig& cfg);

}  // namespace arbor::accel
