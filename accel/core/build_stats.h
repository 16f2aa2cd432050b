#pragma once
/// Statistics every structure reports after its build (design.md §2).
#include <cstddef>
#include <cstdint>
#include <string>

namespace arbor::accel {

struct BuildStats {
    double build_ms = 0.0;
    std::size_t triangles = 0;          ///< triangles in the view
    std::size_t dropped_nonfinite = 0;  ///< triangles skipped because a corner is NaN/Inf
    std::size_t nodes = 0;              ///< all nodes, interior and leaf
    std::size_t leaves = 0;
    std::uint32_t max_depth = 0;        ///< depth of the deepest leaf (root = 0)
    double mean_leaf_depth = 0.0;
    double sah_cost = 0.0;              ///< SAH cost normalized to the root box area
    std::size_t memory_bytes = 0;       ///< bytes of the traversal structure (nodes + leaf data)
    std::size_t build_peak_bytes = 0;   ///< largest temporary memory of the build
    /// A BVH built in compact mode though not asked for: why, the default layout's refusal under
    /// BuildConfig::max_memory ("bvh-sah: its 16-wide SIMD layout needs ..."); empty otherwise.
    std::string compact_fallback;
    double bytes_per_triangle() const { return triangles ? double(memory_bytes) / double(triangles) : 0.0; }
};

}  // namespace arbor::accel
