#pragma once
/// The generalized winding number's two terms, in double: a triangle's exact solid angle and a
/// cluster's far-field (dipole) approximation with its error bound.
///
/// The winding number of a surface around q is the signed solid angle it subtends over 4 pi
/// (Jacobson, Kavan, Sorkine-Hornung, "Robust Inside-Outside Segmentation using Generalized Winding
/// Numbers", SIGGRAPH 2013): 1 inside a closed surface whose triangles turn counter-clockwise seen
/// from outside (normal (v1-v0)x(v2-v0) pointing out), 0 outside, fractional for open surfaces.
/// Far from a cluster of triangles, its sum is replaced by one dipole at the cluster's
/// area-weighted centroid (Barill, Dickson, Schmidt, Levin, Jacobson, "Fast Winding Numbers for
/// Soups and Clouds", SIGGRAPH 2018; the first-order term only).
#include "accel/core/closest_point.h"

#include <cmath>
#include <numbers>

namespace arbor::accel {

namespace detail {

/// s + e = a + b exactly (Knuth's TwoSum).
inline void two_sum(double a, double b, double& s, double& e) {
    s = a + b;
    const double bv = s - a, av = s - bv;
    e = (a - av) + (b - bv);
}

/// a . (b x c) exactly, rounded to double: each 2x2 minor as four exact products' parts (fma), each
/// part times a's component as two more, and the 24 parts summed without error into a
/// nonoverlapping expansion (Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast
/// Robust Geometric Predicates", 1997: Two-Product, Grow-Expansion). Exactly 0 when, and only
/// when, the three vectors are coplanar (barring underflow of a product's error below the normal
/// range).
inline double triple_product_exact(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    double h[25];
    int len = 0;
    const auto add = [&](double q) {  // Grow-Expansion: h stays nonoverlapping, smallest first
        for (int i = 0; i < len; ++i) {
            double s, e;
            two_sum(q, h[i], s, e);
            h[i] = e;
            q = s;
        }
        h[len++] = q;
    };
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3, k = (i + 2) % 3;
        const double p1 = b[j] * c[k], p2 = b[k] * c[j];
        const double parts[4] = {p1, std::fma(b[j], c[k], -p1), -p2, -std::fma(b[k], c[j], -p2)};
        for (const double m : parts) {
            const double p = a[i] * m;
            add(p);
            add(std::fma(a[i], m, -p));
        }
    }
    double sum = 0.0;
    for (int i = 0; i < len; ++i) sum += h[i];  // smallest first: the sign of the largest survives
    return sum;
}

/// x - y for floats, and whether the double result is exact.
inline double difference(float x, float y, bool& exact) {
    double s, e;
    two_sum(double(x), -double(y), s, e);
    exact = exact && e == 0.0;
    return s;
}

}  // namespace detail

/// Triangle (v0, v1, v2)'s winding number around q: its signed solid angle over 4 pi, in
/// (-1/2, 1/2]. Van Oosterom & Strackee, "The Solid Angle of a Plane Triangle", IEEE TBME 1983:
/// with a, b, c the corners minus q, tan(omega / 2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (a.c)|b| +
/// (b.c)|a|), in double.
///
/// A point exactly in the triangle's plane (a.(b x c) = 0: on the triangle, on its edges or
/// corners, or beside it) gets 0, the mean of the two one-sided limits; so a point exactly on a
/// closed mesh gets 1/2 from the rest of the surface on a face, and the interior's share of the
/// directions on an edge or a corner. Deciding that takes exact arithmetic: in double, a point on
/// an edge leaves both a.(b x c) and the denominator as rounding noise (0/0), and its winding number
/// would be anything. So where the double triple product is within 2^-20 of its permanent (well
/// above its rounding error bound), it is computed exactly (detail::triple_product_exact) and the
/// denominator in long double, when the corners minus q are exact in double (float exponents
/// within 29 of each other; else the double values stand). Near a sliver, whose denominator
/// cancels more than long double covers, the result keeps an error above 1e-9 (tests/test_winding.cpp).
inline double triangle_winding(const Vec3f& q, const Vec3f& v0, const Vec3f& v1, const Vec3f& v2) {
    bool exact = true;
    const Vec3d a{detail::difference(v0.x, q.x, exact), detail::difference(v0.y, q.y, exact),
                  detail::difference(v0.z, q.z, exact)};
    const Vec3d b{detail::difference(v1.x, q.x, exact), detail::difference(v1.y, q.y, exact),
                  detail::difference(v1.z, q.z, exact)};
    const Vec3d c{detail::difference(v2.x, q.x, exact), detail::difference(v2.y, q.y, exact),
                  detail::difference(v2.z, q.z, exact)};
    double det = simd::dot(a, simd::cross(b, c));
    // The permanent bounds the terms of det; det's rounding error is below 8 * 2^-53 of it.
    const double perm = std::fabs(a.x) * (std::fabs(b.y * c.z) + std::fabs(b.z * c.y)) +
                        std::fabs(a.y) * (std::fabs(b.z * c.x) + std::fabs(b.x * c.z)) +
                        std::fabs(a.z) * (std::fabs(b.x * c.y) + std::fabs(b.y * c.x));
    if (!(std::fabs(det) > 0x1p-20 * perm) && exact) {
        // Within 2^-20 of the plane, relative to the triangle as seen from q (near its plane, an
        // edge or a corner): det exactly (0 decides), and the denominator, which cancels there
        // too, in long double.
        det = detail::triple_product_exact(a, b, c);
        if (det == 0.0) return 0.0;
        using L = long double;
        const auto len = [](const Vec3d& v) { return std::sqrt(L(v.x) * v.x + L(v.y) * v.y + L(v.z) * v.z); };
        const auto dot = [](const Vec3d& u, const Vec3d& v) { return L(u.x) * v.x + L(u.y) * v.y + L(u.z) * v.z; };
        const L la = len(a), lb = len(b), lc = len(c);
        const L den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
        return double(std::atan2(L(det), den) * (0.5L / std::numbers::pi_v<L>));
    }
    if (det == 0.0) return 0.0;  // also the sign of a signed zero decided nothing
    const double la = simd::length(a), lb = simd::length(b), lc = simd::length(c);
    const double den = la * lb * lc + simd::dot(a, b) * lc + simd::dot(a, c) * lb + simd::dot(b, c) * la;
    return std::atan2(det, den) * (0.5 * std::numbers::inv_pi);
}

/// A cluster of triangles seen from afar: the sum of their area vectors (1/2 (v1-v0)x(v2-v0)),
/// the area-weighted centroid of their centroids, their total unsigned area, and a radius that
/// bounds the distance from `center` to every point of them.
struct Dipole {
    Vec3d center{0.0, 0.0, 0.0};
    Vec3d normal{0.0, 0.0, 0.0};  ///< sum of area vectors (length: area for a flat cluster)
    double area = 0.0;
    double radius = 0.0;
};

/// The far-field winding number of cluster `d` around q: normal . (center - q) / (4 pi |center - q|^3).
inline double dipole_winding(const Dipole& d, const Vec3d& q) {
    const Vec3d r = d.center - q;
    const double r2 = simd::dot(r, r);
    return simd::dot(d.normal, r) / (4.0 * std::numbers::pi * r2 * std::sqrt(r2));
}

/// A bound on |dipole_winding(d, q) - the cluster's exact winding number| for a point at distance
/// `dist` > d.radius from the center: the solid angle's kernel n.(x-q)/|x-q|^3 is -n.grad(1/|x-q|),
/// whose change between the center and any point x of the cluster is at most |x - center| times
/// the Hessian's norm, 2 / (dist - radius)^3; integrated over the area and over 4 pi:
/// area * radius / (2 pi (dist - radius)^3). With dist > beta * radius this is at most
/// 2 beta^2 / (beta - 1)^3 times area / (4 pi dist^2), the cluster's largest possible value.
inline double dipole_error_bound(const Dipole& d, double dist) {
    const double gap = dist - d.radius;
    return d.area * d.radius / (2.0 * std::numbers::pi * gap * gap * gap);
}

}  // namespace arbor::accel
