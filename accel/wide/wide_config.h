#pragma once
/// WideConfig: the settings of the BVHs' SIMD layout, read by the collapse (wide_layout.h) and
/// the width's factory (wide_paths.h). Part of BuildConfig (accel/interface/build_config.h) as `wide`; the
/// defaults are the measured best.
#include <cstdint>

namespace arbor::accel {

struct WideConfig {
    /// Children per node: 4, 8 or 16 (0 = the measured best of this build, wide_paths.h; a width
    /// the build's ISA lacks falls back to the default). `--bvh-width`.
    std::uint32_t width = 0;
    /// A binary subtree with at most this many triangles may become one leaf (the SAH decides; a
    /// binary leaf always stays one). 0 = the width N.
    std::uint32_t merge_triangles = 0;
    /// Most triangles in one leaf (1..65535): bigger binary leaves are split into chunks under
    /// extra nodes (all with the leaf's box).
    std::uint32_t max_leaf_triangles = 65535;
    /// SAH costs of the collapse: one N-wide node test and one N-triangle block test (block / node
    /// = 2, 3 or 4 measured alike).
    float node_cost = 1.0f, block_cost = 3.0f;
    /// Root leaves of at most this many triangles are tested once for a group of incoherent rays
    /// on the single path when enough of the group hit them (wide_shared_leaves.h); 0 = never.
    /// `arbor-bench paths --shared-leaves`.
    std::uint32_t shared_leaf_triangles = 32;
    /// Most bytes the layout's arrays may take (0: no limit): make_wide_layout throws
    /// MemoryLimitError from its plan, before it allocates them. BvhAccel sets it from
    /// BuildConfig::max_memory, less what the build holds already.
    std::uint64_t max_bytes = 0;
};

}  // namespace arbor::accel
