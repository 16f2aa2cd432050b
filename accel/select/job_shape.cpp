#include "accel/select/job_shape.h"

#include "accel/interface/coherence.h"
#include "simd/simd.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace arbor::accel {

namespace {

/// Bounds of the finite vertices (a vertex with a non-finite coordinate is skipped), a register
/// of vertices at a time, without a branch per vertex: this pass over every vertex is the largest
/// part of auto's own work on a small job.
Bounds vertex_bounds(const TriangleView& tris) {
    using V = simd::FloatV;
    constexpr float inf = std::numeric_limits<float>::infinity();
    const V big(std::numeric_limits<float>::max()), up(inf), down(-inf);
    V lx(up), ly(up), lz(up), hx(down), hy(down), hz(down);
    const float *x = tris.x.data(), *y = tris.y.data(), *z = tris.z.data();
    const std::size_t n = tris.vertex_count();
    std::size_t i = 0;
    for (; i + V::size <= n; i += V::size) {
        const V px = V::load_unaligned(x + i), py = V::load_unaligned(y + i), pz = V::load_unaligned(z + i);
        // (|v| <= FLT_MAX is false for NaN and the infinities.)
        const auto ok = (xsimd::abs(px) <= big) & (xsimd::abs(py) <= big) & (xsimd::abs(pz) <= big);
        lx = simd::rmin(simd::select(ok, px, up), lx), hx = simd::rmax(simd::select(ok, px, down), hx);
        ly = simd::rmin(simd::select(ok, py, up), ly), hy = simd::rmax(simd::select(ok, py, down), hy);
        lz = simd::rmin(simd::select(ok, pz, up), lz), hz = simd::rmax(simd::select(ok, pz, down), hz);
    }
    Bounds b;
    b.lo = {simd::hmin(lx), simd::hmin(ly), simd::hmin(lz)};
    b.hi = {-simd::hmin(-hx), -simd::hmin(-hy), -simd::hmin(-hz)};
    for (; i < n; ++i) {
        const Vec3f p{x[i], y[i], z[i]};
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) b.grow(p);
    }
    return b;
}

double median_of(std::vector<double>& v) {
    if (v.empty()) return 0.0;
    const auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

}  // namespace

SceneShape scene_shape(const TriangleView& tris, std::size_t sample) {
    SceneShape s;
    s.triangles = tris.triangle_count();
    s.bounds = vertex_bounds(tris);
    if (s.triangles == 0 || s.bounds.empty()) return s;
    const std::size_t m = std::min(std::max<std::size_t>(sample, 1), s.triangles);
    std::vector<double> diag, thin;
    diag.reserve(m), thin.reserve(m);
    double box_area = 0.0, diag_sum = 0.0;
    for (std::size_t j = 0; j < m; ++j) {
        const std::size_t t = j * s.triangles / m;
        if (!tris.triangle_is_finite(t)) continue;
        const Vec3f a = tris.corner(t, 0), b = tris.corner(t, 1), c = tris.corner(t, 2);
        const Vec3f n = simd::cross(b - a, c - a);
        const double area2 = double(simd::length(n));  // twice the area
        const Bounds box = tris.triangle_bounds(t);
        const Vec3f e = box.extent();
        const double d2 = double(e.x) * e.x + double(e.y) * e.y + double(e.z) * e.z;
        if (!(area2 > 0.0) || !(d2 > 0.0)) continue;
        box_area += box.area();
        diag_sum += std::sqrt(d2);
        diag.push_back(std::sqrt(d2));
        thin.push_back(d2 / area2);
    }
    s.sampled = diag.size();
    if (diag.empty()) return s;
    const double k = double(diag.size());
    const double scene_area = s.bounds.area();
    const Vec3f e = s.bounds.extent();
    const double scene_diag = std::sqrt(double(e.x) * e.x + double(e.y) * e.y + double(e.z) * e.z);
    const double med = median_of(diag);
    s.overlap = scene_area > 0.0 ? double(s.triangles) * (box_area / k) / scene_area : 0.0;
    s.spread = med > 0.0 ? scene_diag / (med * std::sqrt(double(s.triangles))) : 0.0;
    s.size_tail = med > 0.0 ? (diag_sum / k) / med : 0.0;
    s.thinness = median_of(thin);
    return s;
}

RayShape ray_shape(std::span<const Ray> rays, double count, Query query, float scene_diagonal) {
    RayShape r;
    r.rays = count;
    r.query = query;
    r.coherent = r.together = 0.0;
    if (rays.empty()) return r;
    constexpr std::size_t group = 16, groups = 64;
    const float spread = 0.05f * scene_diagonal;
    r.coherent = coherent_fraction(rays, group, spread, groups);
    r.together = coherent_fraction(rays, group, spread, groups, false);
    return r;
}

}  // namespace arbor::accel
