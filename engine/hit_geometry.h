#pragma once
/// The geometry of a ray's hit that the renderer and the ray generator start new rays from: the hit
/// point, the unit geometric normal turned to face the incoming ray, and the triangle's scale for
/// accel::offset_ray_origin.
#include "accel/core/geometry.h"
#include "accel/core/offset_ray.h"
#include "accel/core/ray.h"

#include <cmath>

namespace arbor::engine {

struct HitGeometry {
    accel::Vec3f position{0.0f};           ///< left at 0 unless asked for
    accel::Vec3f normal{0.0f, 0.0f, 1.0f}; ///< facing the incoming ray
    float scale = 0.0f;                     ///< accel::triangle_scale of the triangle (with the position)
    bool valid = false;  ///< false for a zero-area or overflowing triangle (no normal): ignore the hit
};

/// Geometry of `hit` on the triangle of corners v0, v1, v2 for `ray`; the position and scale only
/// `with_position`.
inline HitGeometry hit_geometry(const accel::Vec3f& v0, const accel::Vec3f& v1, const accel::Vec3f& v2,
                                const accel::Ray& ray, const accel::Hit& hit, bool with_position = true) {
    HitGeometry g;
    const accel::Vec3f n = simd::cross(v1 - v0, v2 - v0);
    const float len = simd::length(n);
    if (!(len > 0.0f) || !std::isfinite(len)) return g;
    g.normal = n / len;
    if (simd::dot(g.normal, ray.dir) > 0.0f) g.normal = -g.normal;
    if (with_position) {
        g.position = v0 * (1.0f - hit.u - hit.v) + v1 * hit.u + v2 * hit.v;
        g.scale = accel::triangle_scale(v0, v1, v2);
    }
    g.valid = true;
    return g;
}

/// Geometry of `hit` (on tris) for `ray`; the position and scale only `with_position`.
inline HitGeometry hit_geometry(const accel::TriangleView& tris, const accel::Ray& ray, const accel::Hit& hit,
                                bool with_position = true) {
    return hit_geometry(tris.corner(hit.prim, 0), tris.corner(hit.prim, 1), tris.corner(hit.prim, 2), ray, hit,
                        with_position);
}

}  // namespace arbor::engine
