#pragma once
/// The direction the kd-tree's walks follow (ropes, stack, packet start): the ray's, except that a
/// component whose shear d[k] / dmax underflows to zero in float is taken as zero (its sign kept).
/// The watertight triangle test shears by exactly that quotient (simd/ray_triangle.h, woop_shear), so
/// it sees a ray that does not move along k, and the BVHs' box test follows it (slab_rcp's
/// zero-direction rule, simd/ray_box.h). Walked in double with the true component, a ray lying
/// in a face of the scene box (origin on it, d[k] ~ 1e-42 against d ~ 1e30 along it) left the box
/// at t = 0 and missed the face's triangles the triangle test hits. Found by a search over extreme
/// rays against the fuzzer's ray scene (test 'kdtree stiff: a direction component whose shear
/// underflows ...').
#include "simd/simd.h"
#include "simd/vec3.h"

#include <algorithm>
#include <cmath>

namespace arbor::accel::kd {

/// Whether component `dk` of a direction whose largest |component| is `dmax` shears to zero:
/// |dk| / dmax rounds to 0 in float exactly when the quotient is at most 2^-150 (half the smallest
/// denormal, ties to even), i.e. when |dk| * 2^150 <= dmax; the two exact power-of-two scalings
/// say that without a division (a product past FLT_MAX is +inf, and then the quotient is far
/// from 0). Equal to `dk != 0 && std::fabs(dk) / dmax == 0` (tested).
inline bool shears_to_zero(float dk, float dmax) { return dk != 0.0f && std::fabs(dk) * 0x1p100f * 0x1p50f <= dmax; }
template <class P> inline auto shears_to_zero(const P& dk, const P& dmax) {
    return (dk != P(0.0f)) & (xsimd::abs(dk) * P(0x1p100f) * P(0x1p50f) <= dmax);
}

/// Whether a ray that does not move along axis k (walk direction component 0), with origin `o` on
/// that axis, can meet a triangle of a scene box spanning [lo, hi] on it: the origin must lie in
/// the slab, and the box must have thickness there. A scene of no thickness along k whose plane
/// holds the origin has every triangle coplanar with the ray, and the watertight test misses those
/// (the box test's flat-slab rule, simd/ray_box.h in_flat_slab): nothing to walk.
inline bool flat_axis_can_hit(float o, float lo, float hi) { return o >= lo && o <= hi && lo != hi; }

inline simd::Vec3f walk_direction(const simd::Vec3f& d) {
    const float dmax = std::max(std::fabs(d.x), std::max(std::fabs(d.y), std::fabs(d.z)));
    simd::Vec3f w = d;
    for (int k = 0; k < 3; ++k)
        if (shears_to_zero(d[k], dmax)) w[k] = std::copysign(0.0f, d[k]);
    return w;
}

}  // namespace arbor::accel::kd
