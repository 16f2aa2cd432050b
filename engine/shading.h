#pragma once
/// What a hit looks like once vertex attributes are read: the shading normal interpolated from
/// the corners' normals with the hit's barycentrics, the point secondary rays start from, and the
/// diffuse albedo (material colour x texture x vertex colour). Read only when the render plan says
/// the scene has them (RenderPlan::vertex_normals, textures, vertex_colors).
///
/// The shadow terminator. A shading normal that differs from the triangle's plane lights points
/// that the flat triangle itself hides from the light: shadow rays leaving the flat triangle hit
/// its neighbours (black, blocky patches along the terminator of low-polygon spheres), or, turned
/// the other way, light leaks. Two documented fixes, both here:
///  - rays start from the point Hanika ("Hacking the Shadow Terminator", Ray Tracing Gems II,
///    ch. 4, 2021) lifts off the flat triangle: the hit point projected onto the tangent plane of
///    each corner (only where it lies below that plane), interpolated with the barycentrics. On a
///    curved (convex) surface that point lies on the smooth surface the normals describe, so
///    shadow rays toward a light the shading normal faces leave the mesh instead of grazing the
///    neighbouring triangles; on a flat region it is the hit point itself;
///  - the shading normal is turned to the side of the geometric normal the ray came from, and
///    scattered directions that would go below the geometric surface are mirrored to above it
///    (shading.h: above_surface), so no ray is sent into the surface it leaves.
#include "engine/mesh.h"

namespace arbor::engine {

/// Barycentric weights of a hit (rayfile.md: point = (1-u-v) v0 + u v1 + v v2).
struct Barycentrics {
    float b0, b1, b2;
};
inline Barycentrics barycentrics(float u, float v) { return {1.0f - u - v, u, v}; }

/// The interpolated unit shading normal of triangle `prim` at `b`, on the side of `ng` (the unit
/// geometric normal facing the incoming ray). Corners without a normal use `ng`; a result that
/// is zero, not finite or still on the far side of the surface is `ng`.
Vec3f shading_normal(const Mesh& m, std::uint32_t prim, Barycentrics b, const Vec3f& ng);

/// Hanika's point (above) for the hit at `p`: where secondary rays start (before the usual
/// offset along `ng`). `p` itself when no corner has a normal.
Vec3f terminator_point(const Mesh& m, std::uint32_t prim, Barycentrics b, const Vec3f& p, const Vec3f& ng);

/// `d` when it leaves the surface on `ng`'s side, else `d` mirrored in the surface's plane.
inline Vec3f above_surface(const Vec3f& d, const Vec3f& ng) {
    const float c = simd::dot(d, ng);
    return c > 0.0f ? d : d - ng * (2.0f * c);
}

/// The diffuse albedo at the hit: `diffuse` x the material's texture at the interpolated texture
/// coordinate (when `textures` and the corners have them) x the interpolated vertex colour (when
/// `colors`).
Vec3f albedo_at(const Mesh& m, const Material& mat, std::uint32_t prim, Barycentrics b, bool textures, bool colors);

}  // namespace arbor::engine
