#pragma once
/// Origin offset for rays leaving a surface, so that they do not hit it again.
/// See "A Fast and Robust Method for Avoiding Self-Intersection", C. Wächter and N. Binder,
/// Ray Tracing Gems (2019), ch. 6: the point is moved along the normal by a few ulps of its own
/// coordinates (an integer offset), or by a tiny constant near the origin.
#include "accel/ray.h"

#include <bit>
#include <cstdint>

namespace arbor::accel {

/// Offsets point p (on a surface) along geometric normal n (pointing to the side the new ray
/// leaves towards). n must be of unit length: the offset is int(256 * n[k]) ulps, so a long normal
/// overflows the int. Below |p[k]| = 1/32 the offset is the absolute 1/65536 * n[k], made for
/// scenes of about unit size: in a scene 1e-6 across it moves the origin out of the scene (see
/// the surface-1e-6 row of `arbor stress`).
inline Vec3f offset_ray_origin(const Vec3f& p, const Vec3f& n) {
    constexpr float origin = 1.0f / 32.0f;
    constexpr float float_scale = 1.0f / 65536.0f;
    constexpr float int_scale = 256.0f;
    Vec3f out;
    for (int k = 0; k < 3; ++k) {
        const int off = int(int_scale * n[k]);
        const std::int32_t bits = std::bit_cast<std::int32_t>(p[k]);
        const float moved = std::bit_cast<float>(bits + (p[k] < 0 ? -off : off));
        out[k] = std::fabs(p[k]) < origin ? p[k] + float_scale * n[k] : moved;
    }
    return out;
}

}  // namespace arbor::accel
