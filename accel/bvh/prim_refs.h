#pragma once
/// PrimRefs: the build input shared by every BVH builder (bvh-median, bvh-sah, lbvh). One entry
/// per finite triangle, in triangle order, as structure-of-arrays: its bounding box, its centroid
/// (the centre of that box) and its triangle number. Non-finite triangles are dropped and counted.
#include "accel/core/geometry.h"

#include <cstdint>
#include <vector>

namespace arbor::accel {

struct PrimRefs {
    std::vector<float> lo_x, lo_y, lo_z;  ///< box minimum per reference
    std::vector<float> hi_x, hi_y, hi_z;  ///< box maximum per reference
    std::vector<float> cx, cy, cz;        ///< centroid = lo/2 + hi/2 (finite even near FLT_MAX)
    std::vector<std::uint32_t> prim_ids;  ///< triangle number (index in the TriangleView)
    Bounds bounds;                        ///< union of all boxes (empty when size() == 0)
    Bounds centroid_bounds;               ///< bounds of all centroids (empty when size() == 0)
    std::size_t triangles = 0;            ///< triangles in the view, finite or not
    std::size_t dropped_nonfinite = 0;    ///< triangles left out because a corner is NaN/Inf

    std::size_t size() const { return prim_ids.size(); }
    bool empty() const { return prim_ids.empty(); }
    Bounds box(std::size_t i) const { return {{lo_x[i], lo_y[i], lo_z[i]}, {hi_x[i], hi_y[i], hi_z[i]}}; }
    Vec3f centroid(std::size_t i) const { return {cx[i], cy[i], cz[i]}; }
    /// Bytes held by the arrays (for build peak memory).
    std::size_t memory_bytes() const { return size() * (9 * sizeof(float) + sizeof(std::uint32_t)); }
};

/// Fills PrimRefs from the triangles with tbb::parallel_for over fixed blocks. Deterministic: the
/// finite triangles keep their relative order (per-block counts, then an exclusive prefix sum gives
/// each block its output offset) and the bounds are exact min/max, so the result is bit-identical
/// for any thread count.
PrimRefs make_prim_refs(const TriangleView& tris);

}  // namespace arbor::accel
