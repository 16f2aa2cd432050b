#pragma once
/// BuildPrims: what the BVH builders (bvh-median, bvh-sah and its sweep reference, lbvh) work on.
/// One 32-byte record per finite triangle, in triangle order: its box and its triangle number (the
/// centroid, lo/2 + hi/2, is worked out where it is needed: the same bits as PrimRefs::cx/cy/cz),
/// with the bounds of all boxes and of all centroids. make_accel makes them in one pass straight
/// from the triangles (32 bytes a triangle, where PrimRefs and then BuildPrims made from them took
/// 40 + 32: in a fresh process every byte a build touches first is a page the kernel zeroes);
/// the builders' PrimRefs entry points make the same
/// records from PrimRefs, so both give bit-identical trees.
#include "accel/bvh/prim_refs.h"
#include "accel/core/geometry.h"
#include "accel/util/uninit_vector.h"

#include <cstddef>
#include <cstdint>

namespace arbor::accel {

struct alignas(16) BuildPrim {
    float lo[3];
    std::uint32_t id;  ///< triangle number (index in the TriangleView)
    float hi[3];
    std::uint32_t pad;

    /// The same centroid as PrimRefs (lo/2 + hi/2, bit for bit).
    float centroid(int axis) const { return lo[axis] * 0.5f + hi[axis] * 0.5f; }
    Vec3f centroid() const { return {centroid(0), centroid(1), centroid(2)}; }
    Bounds box() const { return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}; }
};
static_assert(sizeof(BuildPrim) == 32);

struct BuildPrims {
    UninitVector<BuildPrim> prims;  ///< one per finite triangle, in triangle order (builders reorder them)
    Bounds bounds;                  ///< union of all boxes (empty when there are none)
    Bounds centroid_bounds;         ///< bounds of all centroids (empty when there are none)
    std::size_t triangles = 0;          ///< triangles in the view, finite or not
    std::size_t dropped_nonfinite = 0;  ///< triangles left out because a corner is NaN/Inf

    std::size_t size() const { return prims.size(); }
    bool empty() const { return prims.empty(); }
    std::size_t memory_bytes() const { return prims.capacity() * sizeof(BuildPrim); }
};

/// Straight from the triangles (for_finite_triangles, finite_triangles.h): parallel, into an array
/// that is not zeroed first; bit-identical for any thread count.
BuildPrims make_build_prims(const TriangleView& tris);
/// The same records from PrimRefs (parallel copy).
BuildPrims make_build_prims(const PrimRefs& refs);

}  // namespace arbor::accel
