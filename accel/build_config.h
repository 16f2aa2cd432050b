#pragma once
/// Build settings shared by all structures. Every field has a documented default; there are no
/// global knobs.
#include <cstdint>

namespace arbor::accel {

struct BuildConfig {
    /// Maximum triangles per BVH leaf (bvh-median splits down to this; SAH and LBVH use it as the
    /// cap). The seed report used 1.
    std::uint32_t max_leaf_size = 4;
    /// Binned SAH: number of bins per axis (16..32 is the useful range).
    std::uint32_t sah_bins = 16;
    /// SAH costs, relative: traversal step vs one ray/triangle test.
    float traversal_cost = 1.0f;
    float intersection_cost = 1.0f;
    /// Below this many primitives a recursive build runs serially (bvh v2 and Embree use 1024).
    std::uint32_t parallel_threshold = 1024;
    /// kd-tree: clip triangles to the node box when computing split candidates (perfect splits).
    bool kd_perfect_splits = true;
    /// kd-tree: factor on the SAH cost of a split that cuts off empty space (one side holds no
    /// triangle); Wald & Havran's lambda = 0.8, i.e. such splits look 20% cheaper. 1 = no bonus.
    float kd_empty_bonus = 0.8f;
    /// Upper bound on build memory in bytes (0 = no limit); a build that would exceed it throws.
    std::uint64_t max_memory = 0;
};

}  // namespace arbor::accel
