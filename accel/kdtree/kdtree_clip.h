#pragma once
/// Conservative bounds of a triangle clipped to a box, for the kd-tree's perfect splits
/// (Havran 2000; Wald & Havran 2006, §4.3).
///
/// Robustness: a full Sutherland-Hodgman clip re-intersects already clipped (rounded) points, and an
/// edge nearly parallel to a plane can then move far. Here every intersection is computed from the
/// original float corners only (one slab at a time), the result is padded by a bound on its rounding
/// error and rounded outward to float, and slabs are intersected. So the result always contains the
/// exact clipped triangle, and it is empty only when the triangle exactly misses the box.
#include "accel/core/geometry.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace arbor::accel {

namespace detail {
/// The next float below / above f (f not NaN; -inf and +inf stay).
inline float step_down(float f) {
    if (f == 0.0f) return -std::numeric_limits<float>::denorm_min();
    const auto u = std::bit_cast<std::uint32_t>(f);
    return f == -INFINITY ? f : std::bit_cast<float>(f > 0.0f ? u - 1 : u + 1);
}
inline float step_up(float f) { return -step_down(-f); }
/// Largest float <= x and smallest float >= x.
inline float float_down(double x) {
    const float f = float(x);
    return double(f) > x ? step_down(f) : f;
}
inline float float_up(double x) {
    const float f = float(x);
    return double(f) < x ? step_up(f) : f;
}
}  // namespace detail

/// Bounds of triangle (a, b, c) intersected with the slab lo <= p[axis] <= hi, conservative; empty
/// when the triangle lies entirely outside the slab (decided exactly: corners are compared with the
/// planes, never interpolated). Coordinates along `axis` are exact.
inline Bounds clip_triangle_to_slab(const Vec3f& a, const Vec3f& b, const Vec3f& c, int axis, float lo, float hi) {
    const Vec3f v[3] = {a, b, c};
    Bounds r;
    for (int i = 0; i < 3; ++i)
        if (v[i][axis] >= lo && v[i][axis] <= hi) r.grow(v[i]);
    for (int i = 0; i < 3; ++i) {
        const Vec3f& p = v[i];
        const Vec3f& q = v[(i + 1) % 3];
        for (const float plane : {lo, hi}) {
            // Strictly opposite sides: the edge crosses the plane between its corners.
            if (!((p[axis] < plane && q[axis] > plane) || (p[axis] > plane && q[axis] < plane))) continue;
            // p and q are floats, so differences are exact in double; t has one rounding.
            const double t = (double(plane) - p[axis]) / (double(q[axis]) - p[axis]);
            Vec3f lo_pt, hi_pt;
            for (int j = 0; j < 3; ++j) {
                if (j == axis) {
                    lo_pt[j] = hi_pt[j] = plane;
                } else if (p[j] == q[j]) {
                    lo_pt[j] = hi_pt[j] = p[j];  // the coordinate does not change along the edge: exact
                } else {
                    const double x = double(p[j]) + (double(q[j]) - p[j]) * t;
                    // Rounding error of t, the product and the sum: far below this bound.
                    const double err = (std::fabs(double(p[j])) + std::fabs(double(q[j]))) * 0x1p-48;
                    lo_pt[j] = detail::float_down(x - err);
                    hi_pt[j] = detail::float_up(x + err);
                }
            }
            r.grow(lo_pt);
            r.grow(hi_pt);
        }
    }
    return r;
}

/// Intersection of two boxes (empty when they do not overlap; a shared face gives a flat box).
inline Bounds intersect(const Bounds& x, const Bounds& y) {
    Bounds r;
    r.lo = simd::vmax(x.lo, y.lo);
    r.hi = simd::vmin(x.hi, y.hi);
    return r;
}

/// Conservative bounds of triangle (a, b, c) inside `box`, given `known`, bounds already known to
/// contain the triangle's part inside a box enclosing `box` (the parent node's clipped bounds).
/// `axis` is the axis along which `box` was cut from that enclosing box. Empty only when the
/// triangle does not meet `box`.
inline Bounds clip_triangle_bounds(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Bounds& known,
                                   const Bounds& box, int axis) {
    Bounds r = intersect(known, box);
    if (r.empty()) return Bounds{};
    r = intersect(r, clip_triangle_to_slab(a, b, c, axis, box.lo[axis], box.hi[axis]));
    for (int j = 0; j < 3 && !r.empty(); ++j) {
        if (j == axis) continue;
        // A triangle wholly inside this slab gains nothing from clipping to it.
        const float lo = r.lo[j], hi = r.hi[j];
        if (a[j] >= lo && a[j] <= hi && b[j] >= lo && b[j] <= hi && c[j] >= lo && c[j] <= hi) continue;
        r = intersect(r, clip_triangle_to_slab(a, b, c, j, lo, hi));
    }
    return r.empty() ? Bounds{} : r;
}

}  // namespace arbor::accel
