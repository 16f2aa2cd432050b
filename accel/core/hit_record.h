#pragma once
/// HitRecord: where every leaf of every structure and path puts the hits its triangle tests find.
/// One offer(t, prim, u, v), one rule (simd/ray.h, closer): the closest hit is the smallest t, and
/// on equal t the lowest prim, so all structures and paths give the same record for a ray, bit
/// for bit, whatever order they find its candidates in (rays through shared edges and vertices,
/// coplanar duplicates: tests/test_ties.cpp). An any-hit record keeps the first hit offered and the
/// walk ends there. The packet paths keep the same rule lane by lane (simd::offer_lanes), and SIMD
/// leaf blocks hold each leaf's triangles in ascending prim order, so that the lowest of the lanes
/// tied at the smallest t (simd::closest_lane) is the lowest prim.
///
/// A new query kind that keeps hits differently (all hits, say) is another record with the same
/// offer(); the walks only read offer()'s answer and, for closest hits, lower their tfar to t.
#include "accel/core/ray.h"

namespace arbor::accel {

template <bool AnyHit> struct HitRecord {
    Hit hit;

    /// A hit of the triangle test (t within the ray's [tnear, current tfar]); true when kept. A
    /// closest-hit walk then lowers its tfar to t (ties at t are still tested: the tests accept
    /// t == tfar), an any-hit walk ends.
    bool offer(float t, std::uint32_t prim, float u, float v) {
        if constexpr (!AnyHit)
            if (!simd::closer(t, prim, hit)) return false;
        hit = {t, prim, u, v};
        return true;
    }
};

}  // namespace arbor::accel
