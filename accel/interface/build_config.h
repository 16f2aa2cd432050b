#pragma once
/// BuildConfig: everything make_accel (accel.h) needs to build a structure, as one struct of
/// per-purpose parts, each defined beside the code that reads it and handed to that code whole
/// (no field is copied from one struct to another):
///   bvh        BvhBuildConfig  bvh/bvh_build_config.h  the binary BVH builders
///   kd         KdBuildConfig   kdtree/kdtree_config.h  the kd-tree builder
///   wide       WideConfig      wide/wide_config.h      the BVHs' SIMD layout (width, collapse)
///   kd_blocks  KdBlockConfig   kdtree/kdtree_config.h  the kd-tree's SIMD leaf blocks
///   packets    PacketConfig    core/simd_paths.h       the packet path of both SIMD structures
/// and the two settings of the build as a whole: which layouts to make, and the memory limit.
/// Every field has a documented default; there are no global knobs.
#include "accel/bvh/bvh_build_config.h"
#include "accel/core/simd_paths.h"
#include "accel/kdtree/kdtree_config.h"
#include "accel/wide/wide_config.h"

#include <cstdint>

namespace arbor::accel {

/// Which traversal layouts a structure builds: `all` (every path can be traced: tests, benchmarks),
/// `scalar` (only the reference path's layout) or `simd` (only the layouts of the SIMD paths
/// `single` and `packet`, which `best` takes). A path whose layout was not built is traced on one
/// that was (Accel::offer says which exist; every path gives the same answers).
enum class Layouts : std::uint8_t { all, scalar, simd };

struct BuildConfig {
    BvhBuildConfig bvh;
    KdBuildConfig kd;
    WideConfig wide;
    KdBlockConfig kd_blocks;
    PacketConfig packets;
    /// Traversal layouts to build (BVHs: the two-box scalar layout and/or the N-wide SIMD layout;
    /// kd-tree: its SIMD leaf blocks or not). The command line builds only what the requested path
    /// reads (interface/path_policy.h, layouts_for).
    Layouts layouts = Layouts::all;
    /// Upper bound on build memory in bytes (0 = no limit); a build that would exceed it throws
    /// MemoryLimitError (factory/memory_estimate.h): checked from the triangle count before building,
    /// by the top-down BVH and kd-tree builders as they grow, by the BVHs' layouts from their sizes
    /// before they are made, and against the measured peak afterwards. A BVH built for the SIMD
    /// paths only (layouts == simd) whose default layout would not fit is built in compact mode
    /// when that fits (BuildStats::compact_fallback says why). `--max-memory`.
    std::uint64_t max_memory = 0;
    /// Compact mode (BVHs only; the other structures ignore it): the SIMD layout is kept as
    /// wide/compact_layout.h's quantized nodes and leaves of blocks with their own vertex copies,
    /// about half the bytes per triangle, traced on the `single` and `packet` paths (the scalar
    /// path falls back to them; no scalar layout is built). `--compact`.
    bool compact = false;
};

}  // namespace arbor::accel
