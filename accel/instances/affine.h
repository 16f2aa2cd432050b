#pragma once
/// Affine transforms of instances: a 3x4 matrix, row-major, [A | t], mapping an object-space point
/// p to the world point A p + t. Everything is double: a transform given in float is exact in
/// double, and its inverse, the rays carried into object space and the points carried back are
/// rounded to float once, at the end.
#include "accel/core/geometry.h"

#include <array>
#include <cmath>
#include <optional>
#include <string>

namespace arbor::accel {

struct Affine {
    /// Row-major 3x4: m[4 r + c]; column 3 is the translation.
    std::array<double, 12> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};

    double at(int r, int c) const { return m[std::size_t(4 * r + c)]; }
    /// A p + t.
    std::array<double, 3> point(double x, double y, double z) const {
        return {at(0, 0) * x + at(0, 1) * y + at(0, 2) * z + at(0, 3), at(1, 0) * x + at(1, 1) * y + at(1, 2) * z + at(1, 3),
                at(2, 0) * x + at(2, 1) * y + at(2, 2) * z + at(2, 3)};
    }
    /// A v (a direction: no translation).
    std::array<double, 3> vector(double x, double y, double z) const {
        return {at(0, 0) * x + at(0, 1) * y + at(0, 2) * z, at(1, 0) * x + at(1, 1) * y + at(1, 2) * z,
                at(2, 0) * x + at(2, 1) * y + at(2, 2) * z};
    }
    /// det A: negative for a mirroring transform (it flips a triangle's orientation).
    double det() const {
        return at(0, 0) * (at(1, 1) * at(2, 2) - at(1, 2) * at(2, 1)) - at(0, 1) * (at(1, 0) * at(2, 2) - at(1, 2) * at(2, 0)) +
               at(0, 2) * (at(1, 0) * at(2, 1) - at(1, 1) * at(2, 0));
    }
    /// Exactly the identity (then rays are passed on untouched, bit for bit).
    bool is_identity() const { return m == Affine{}.m; }

    /// The inverse transform (object <- world). Only for transforms that check_affine accepts.
    Affine inverse() const {
        const double d = det();
        Affine r;
        // The adjugate over the determinant, then -A^-1 t.
        r.m[0] = (at(1, 1) * at(2, 2) - at(1, 2) * at(2, 1)) / d;
        r.m[1] = (at(0, 2) * at(2, 1) - at(0, 1) * at(2, 2)) / d;
        r.m[2] = (at(0, 1) * at(1, 2) - at(0, 2) * at(1, 1)) / d;
        r.m[4] = (at(1, 2) * at(2, 0) - at(1, 0) * at(2, 2)) / d;
        r.m[5] = (at(0, 0) * at(2, 2) - at(0, 2) * at(2, 0)) / d;
        r.m[6] = (at(0, 2) * at(1, 0) - at(0, 0) * at(1, 2)) / d;
        r.m[8] = (at(1, 0) * at(2, 1) - at(1, 1) * at(2, 0)) / d;
        r.m[9] = (at(0, 1) * at(2, 0) - at(0, 0) * at(2, 1)) / d;
        r.m[10] = (at(0, 0) * at(1, 1) - at(0, 1) * at(1, 0)) / d;
        const auto t = r.vector(at(0, 3), at(1, 3), at(2, 3));
        r.m[3] = -t[0], r.m[7] = -t[1], r.m[11] = -t[2];
        return r;
    }

    /// The uniform scale s when A = s R with R orthogonal (a rotation or a mirror), to 1e-6 of s^2
    /// in every entry of A^T A; nullopt for a non-uniform scale or a shear.
    std::optional<double> similarity_scale() const {
        double g[3][3];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) g[i][j] = at(0, i) * at(0, j) + at(1, i) * at(1, j) + at(2, i) * at(2, j);
        const double s2 = (g[0][0] + g[1][1] + g[2][2]) / 3.0;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                if (std::fabs(g[i][j] - (i == j ? s2 : 0.0)) > 1e-6 * s2) return std::nullopt;
        return std::sqrt(s2);
    }
};

/// What is wrong with a transform ("" when it can place an instance): a non-finite entry, or a
/// singular (or numerically singular: |det A| below 1e-12 of the product of its row lengths) A.
inline std::string check_affine(const Affine& a) {
    for (std::size_t i = 0; i < 12; ++i)
        if (!std::isfinite(a.m[i]))
            return "entry [" + std::to_string(i / 4) + "][" + std::to_string(i % 4) + "] is not finite (" +
                   std::to_string(a.m[i]) + ")";
    double rows = 1.0;
    for (int r = 0; r < 3; ++r) rows *= std::sqrt(a.at(r, 0) * a.at(r, 0) + a.at(r, 1) * a.at(r, 1) + a.at(r, 2) * a.at(r, 2));
    const double d = a.det();
    if (!(std::fabs(d) > 1e-12 * rows)) return "the 3x3 part is singular (det " + std::to_string(d) + "): it cannot be inverted";
    const Affine inv = a.inverse();
    for (const double v : inv.m)
        if (!std::isfinite(v)) return "its inverse overflows";
    return {};
}

/// The world box of an object box under `a`: its 8 corners carried over in double, the box of
/// them rounded outwards to float (so it contains every carried-over point of the object box).
inline Bounds transform_bounds(const Affine& a, const Bounds& b) {
    Bounds out;
    if (b.empty()) return out;
    for (int k = 0; k < 8; ++k) {
        const auto p = a.point(k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y, k & 4 ? b.hi.z : b.lo.z);
        for (int c = 0; c < 3; ++c) {
            const float lo = std::nextafter(float(p[std::size_t(c)]), -INFINITY);
            const float hi = std::nextafter(float(p[std::size_t(c)]), INFINITY);
            out.lo[c] = std::min(out.lo[c], lo);
            out.hi[c] = std::max(out.hi[c], hi);
        }
    }
    return out;
}

}  // namespace arbor::accel
