#pragma once
/// What Accel::refit reports: the tree's quality after the refit against the tree as last built.
#include "accel/core/geometry.h"

namespace arbor::accel {

struct RefitResult {
    /// The refitted tree's SAH cost, normalized to its root box's area (wide/wide_refit.h,
    /// bvh/bvh2_refit.h: the cost of the layout the SIMD paths walk, else of the scalar one).
    double sah_cost = 0.0;
    /// The same measure of the same layout right after its last build from scratch: the estimate
    /// of what a fresh build over the new positions would cost (normalized costs do not change
    /// when a whole mesh moves or scales; a deformation changes a fresh tree's much less than an
    /// old tree's).
    double built_sah_cost = 0.0;
    double ms = 0.0;  ///< wall time of the refit
    /// The box of the structure's triangles at their new positions (empty when it holds none).
    Bounds bounds;

    /// sah_cost / built_sah_cost (1 when either is 0: nothing to compare).
    double ratio() const { return sah_cost > 0.0 && built_sah_cost > 0.0 ? sah_cost / built_sah_cost : 1.0; }
};

}  // namespace arbor::accel
