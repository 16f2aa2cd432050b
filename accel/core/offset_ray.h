#pragma once
/// Origin offset for rays leaving a surface, so that they do not hit it again.
/// See "A Fast and Robust Method for Avoiding Self-Intersection", C. Wächter and N. Binder,
/// Ray Tracing Gems (2019), ch. 6: the point is moved along the normal by a few ulps of its own
/// coordinates (an integer offset), or by a tiny constant near the origin.
#include "accel/core/ray.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace arbor::accel {

/// Largest |coordinate| of a triangle's corners: what the rounding error of the watertight test's
/// t scales with (its terms are products of corner coordinates relative to the ray origin).
inline float triangle_scale(const Vec3f& v0, const Vec3f& v1, const Vec3f& v2) {
    float m = 0.0f;
    for (int k = 0; k < 3; ++k) m = std::max({m, std::fabs(v0[k]), std::fabs(v1[k]), std::fabs(v2[k])});
    return m;
}

/// Offsets point p (on a surface) along geometric normal n (pointing to the side the new ray
/// leaves towards). n must be of unit length: the offset is int(256 * n[k]) ulps, so a long normal
/// overflows the int. Below |p[k]| = 1/32 the offset is the absolute 1/65536 * n[k], made for
/// scenes of about unit size: in a scene 1e-6 across it moves the origin out of the scene (see
/// the surface-1e-6 row of `arbor stress`).
///
/// `scale` (triangle_scale of the triangle p lies on) adds 8 ulps of it along n: the watertight
/// test's t has an absolute error of a few ulps of the corners' magnitude however close the origin
/// is to the plane, so a point near the origin on a big triangle needs more than its own ulps.
/// Measured on the stadium floor (corners at +-1000, hit points at y = 0): 2^-16 alone re-hit the
/// floor on 1066 of 16384 shadow and 2598 of 16384 diffuse rays, >= 4 ulps of 1000 on none.
inline Vec3f offset_ray_origin(const Vec3f& p, const Vec3f& n, float scale = 0.0f) {
    constexpr float origin = 1.0f / 32.0f;
    constexpr float float_scale = 1.0f / 65536.0f;
    constexpr float int_scale = 256.0f;
    const float extra = std::isfinite(scale) ? scale * 0x1p-21f : 0.0f;  // 8 ulps of scale
    Vec3f out;
    for (int k = 0; k < 3; ++k) {
        const int off = int(int_scale * n[k]);
        const std::int32_t bits = std::bit_cast<std::int32_t>(p[k]);
        const float moved = std::bit_cast<float>(bits + (p[k] < 0 ? -off : off));
        out[k] = (std::fabs(p[k]) < origin ? p[k] + float_scale * n[k] : moved) + extra * n[k];
    }
    return out;
}

}  // namespace arbor::accel
