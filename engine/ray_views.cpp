#include "engine/ray_views.h"

#include "engine/sampling.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace arbor::engine {

namespace {

/// The seed's k-th uniform number in [0, 1).
float draw(std::uint64_t seed, std::uint64_t k) { return float(mix64(mix64(seed ^ 0x5EED5EEDull) + k) >> 40) * 0x1p-24f; }

Vec3f direction(float u1, float u2) {
    const float z = 1.0f - 2.0f * u1;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 2.0f * std::numbers::pi_v<float> * u2;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

/// A point within `radius` of the origin (uniform direction, uniform distance).
Vec3f jitter(std::uint64_t seed, std::uint64_t k, float radius) {
    return direction(draw(seed, k), draw(seed, k + 1)) * (radius * draw(seed, k + 2));
}

/// The share of the surface area whose plane has `eye` and `light` on the same side.
double lit_share(const accel::TriangleView& tris, Vec3f eye, Vec3f light) {
    double both = 0.0, all = 0.0;
    for (std::size_t t = 0; t < tris.triangle_count(); ++t) {
        const Vec3f a = tris.corner(t, 0), n = simd::cross(tris.corner(t, 1) - a, tris.corner(t, 2) - a);
        const double area = double(simd::length(n));
        all += area;
        if (simd::dot(n, eye - a) * simd::dot(n, light - a) > 0.0f) both += area;
    }
    return all > 0.0 ? both / all : 1.0;
}

}  // namespace

void place_seeded_view(RayGenScene& gen, const Scene& scene, std::uint64_t seed, bool own_camera) {
    const Sphere s = bounding_sphere(gen.bounds);
    const Vec3f ext = gen.bounds.extent();
    const float size = std::max(ext.x, std::max(ext.y, ext.z));
    if (own_camera) {
        Camera c = scene.camera;
        const float dist = simd::length(c.eye - c.look_at);
        c.eye = c.eye + jitter(seed, 0, 0.10f * dist);
        c.look_at = c.look_at + jitter(seed, 3, 0.05f * dist);
        gen.camera = c;
        if (!scene.lights.empty()) {
            gen.light = scene.lights.front().position + jitter(seed, 6, 0.10f * size);
        } else {
            const Vec3f u{draw(seed, 9), draw(seed, 10), draw(seed, 11)};
            gen.light = gen.bounds.lo + Vec3f{ext.x * (0.2f + 0.6f * u.x), ext.y * (0.2f + 0.6f * u.y), ext.z * (0.2f + 0.6f * u.z)};
        }
        return;
    }
    const Vec3f dir = direction(draw(seed, 0), draw(seed, 1));  // from the centre to the camera
    const float distance = 1.6f + 1.9f * draw(seed, 2);  // in radii
    const float zoom = 0.55f + 0.45f * draw(seed, 3);    // share of the sphere disk's width in view
    Camera c;
    c.look_at = s.center + jitter(seed, 4, 0.15f * s.radius);
    c.eye = s.center + dir * (distance * s.radius);
    // The up vector must not be parallel to the view direction.
    c.up = std::abs(dir.y) > 0.9f ? Vec3f{0.0f, 0.0f, 1.0f} : Vec3f{0.0f, 1.0f, 0.0f};
    // As framed_camera: a vertical field of view whose image diagonal spans `zoom` of the sphere's
    // angular diameter at 4:3.
    const float half_diag = std::tan(zoom * 0.97f * std::asin(1.0f / distance));
    const float aspect = 4.0f / 3.0f;
    c.vfov_degrees = 2.0f * std::atan(half_diag / std::sqrt(1.0f + aspect * aspect)) * 180.0f / std::numbers::pi_v<float>;
    gen.camera = c;
    // The light on the camera's side of the centre, drawn again (up to 16 times) while less than
    // a fifth of the surface area has camera and light on the same side: behind a flat model (the
    // alligator) it would leave no lit surface in view and no shadow ray to make.
    for (std::uint64_t k = 0; k < 16; ++k) {
        Vec3f ldir = direction(draw(seed, 7 + 3 * k), draw(seed, 8 + 3 * k));
        if (simd::dot(ldir, dir) < 0.0f) ldir = ldir * -1.0f;
        gen.light = s.center + ldir * ((1.5f + 2.5f * draw(seed, 9 + 3 * k)) * s.radius);
        if (lit_share(gen.tris, c.eye, gen.light) >= 0.2) break;
    }
}

}  // namespace arbor::engine
