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

/// Triangle (q + a, q + b, q + c)'s winding number around q: its signed solid angle over 4 pi, in
/// (-1/2, 1/2]. Van Oosterom & Strackee, "The Solid Angle of a Plane Triangle", IEEE TBME 1983:
/// tan(omega / 2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|).
/// A point exactly in the triangle's plane (a.(b x c) == 0: on the triangle, on its edges or
/// corners, or beside it) gets 0, the mean of the two one-sided limits; so a point on a face of a
/// closed mesh gets 1/2 from the rest of the surface, on an edge or corner the fraction of the
/// solid angle the interior takes there.
inline double triangle_winding(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const double det = simd::dot(a, simd::cross(b, c));
    if (det == 0.0) return 0.0;  // also the sign of a signed zero decided nothing
    const double la = simd::length(a), lb = simd::length(b), lc = simd::length(c);
    const double den = la * lb * lc + simd::dot(a, b) * lc + simd::dot(a, c) * lb + simd::dot(b, c) * la;
    return std::atan2(det, den) * (0.5 * std::numbers::inv_pi);
}

/// Triangle (v0, v1, v2)'s winding number around q. Float corners and point: their differences
/// are exact in double unless the exponents differ by more than 29.
inline double triangle_winding(const Vec3f& q, const Vec3f& v0, const Vec3f& v1, const Vec3f& v2) {
    const Vec3d p = to_double(q);
    return triangle_winding(to_double(v0) - p, to_double(v1) - p, to_double(v2) - p);
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
