#pragma once
/// Closest points on triangles: the point-triangle distance in double precision, the record a
/// closest-point query returns (PointHit) and the one rule every structure uses to keep the better
/// of two candidates (PointSearch::offer), so that all structures give the same record.
///
/// The distance is exact up to double rounding (the float inputs are exact in double; the closest
/// point is found by Voronoi regions, Ericson, "Real-Time Collision Detection", 2005, 5.1.5), so a
/// point 1e6 away from a 1e-3 triangle still gets its distance to ~1e-16 relative before the final
/// rounding to float. Traversals prune boxes with a float distance made conservative by
/// PointSearch::prune_bound.
#include "accel/core/geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace arbor::accel {

using Vec3d = simd::Vec3<double>;

inline Vec3d to_double(const Vec3f& v) { return {double(v.x), double(v.y), double(v.z)}; }

/// The answer for one query point: the nearest point of the scene within the query's max_distance,
/// on triangle `prim` at barycentrics (u, v) (point = (1-u-v) v0 + u v1 + v v2). Nothing within
/// reach (or a non-finite query point): distance = +inf, prim = invalid_prim, the rest 0.
struct PointHit {
    float distance = std::numeric_limits<float>::infinity();
    std::uint32_t prim = invalid_prim;
    Vec3f point{0.0f, 0.0f, 0.0f};
    float u = 0.0f, v = 0.0f;

    bool is_hit() const { return prim != invalid_prim; }
};

/// The closest point of triangle (a, b, c) to p: its squared distance and barycentrics (weights of
/// b and c). Degenerate triangles (collinear or coincident corners) are handled as their edges.
struct TrianglePoint {
    double dist2;
    double u, v;
};

namespace detail {
template <class R> struct Candidate {
    R dist2, u, v;
};
template <class R> inline R dist2(const simd::Vec3<R>& a, const simd::Vec3<R>& b) {
    const simd::Vec3<R> d = a - b;
    return simd::dot(d, d);
}
/// Closest point of segment [a, b] to p as the weight t of b (a + t (b - a)).
template <class R> inline R segment_param(const simd::Vec3<R>& p, const simd::Vec3<R>& a, const simd::Vec3<R>& b) {
    const simd::Vec3<R> ab = b - a;
    const R len2 = simd::dot(ab, ab);
    if (!(len2 > R(0))) return R(0);
    const R t = simd::dot(p - a, ab) / len2;
    return t <= R(0) ? R(0) : (t >= R(1) ? R(1) : t);
}

/// The nearest of the three edges (exact for a degenerate triangle, which is its edges).
template <class R>
inline Candidate<R> closest_on_edges(const simd::Vec3<R>& p, const simd::Vec3<R>& a, const simd::Vec3<R>& b,
                                     const simd::Vec3<R>& c) {
    const R tab = segment_param(p, a, b), tac = segment_param(p, a, c), tbc = segment_param(p, b, c);
    const R dab = dist2(p, a + (b - a) * tab), dac = dist2(p, a + (c - a) * tac), dbc = dist2(p, b + (c - b) * tbc);
    Candidate<R> r{dab, tab, R(0)};
    if (dac < r.dist2) r = {dac, R(0), tac};
    if (dbc < r.dist2) r = {dbc, R(1) - tbc, tbc};
    return r;
}

/// Ericson's walk over the Voronoi regions: vertex regions of a, b, c, edge regions of ab, ac, bc,
/// else the face. `ok` is false when the face weights came out outside the triangle (a triangle
/// too thin for the face region's arithmetic).
template <class R>
inline Candidate<R> closest_by_regions(const simd::Vec3<R>& p, const simd::Vec3<R>& a, const simd::Vec3<R>& b,
                                       const simd::Vec3<R>& c, bool& ok) {
    ok = true;
    const simd::Vec3<R> ab = b - a, ac = c - a, ap = p - a;
    const R d1 = simd::dot(ab, ap), d2 = simd::dot(ac, ap);
    if (d1 <= R(0) && d2 <= R(0)) return {dist2(p, a), R(0), R(0)};
    const simd::Vec3<R> bp = p - b;
    const R d3 = simd::dot(ab, bp), d4 = simd::dot(ac, bp);
    if (d3 >= R(0) && d4 <= d3) return {dist2(p, b), R(1), R(0)};
    const R vc = d1 * d4 - d3 * d2;
    if (vc <= R(0) && d1 >= R(0) && d3 <= R(0)) {
        const R w = d1 / (d1 - d3);
        return {dist2(p, a + ab * w), w, R(0)};
    }
    const simd::Vec3<R> cp = p - c;
    const R d5 = simd::dot(ab, cp), d6 = simd::dot(ac, cp);
    if (d6 >= R(0) && d5 <= d6) return {dist2(p, c), R(0), R(1)};
    const R vb = d5 * d2 - d1 * d6;
    if (vb <= R(0) && d2 >= R(0) && d6 <= R(0)) {
        const R w = d2 / (d2 - d6);
        return {dist2(p, a + ac * w), R(0), w};
    }
    const R va = d3 * d6 - d5 * d4;
    if (va <= R(0) && d4 - d3 >= R(0) && d5 - d6 >= R(0)) {
        const R w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {dist2(p, b + (c - b) * w), R(1) - w, w};
    }
    const R sum = va + vb + vc;  // = |ab x ac|^2
    const R u = vb / sum, v = vc / sum;
    ok = u >= R(0) && v >= R(0) && u + v <= R(1);  // false for NaN too
    return {ok ? dist2(p, a + ab * u + ac * v) : R(0), u, v};
}

/// For thin triangles: the plane projection when it falls inside (its weights as triple products
/// of p itself with the normal, so the projected point is never formed), else the nearest edge.
/// In long double the corners' differences, the normal and the triple products are exact or
/// nearly so for float corners, where the region walk's barycentrics lose digits.
template <class R>
inline Candidate<R> closest_thin(const simd::Vec3<R>& p, const simd::Vec3<R>& a, const simd::Vec3<R>& b,
                                 const simd::Vec3<R>& c) {
    const Candidate<R> e = closest_on_edges(p, a, b, c);
    const simd::Vec3<R> n = simd::cross(b - a, c - a);
    const R n2 = simd::dot(n, n);
    if (!(n2 > R(0))) return e;
    const R wa = simd::dot(simd::cross(c - b, p - b), n), wb = simd::dot(simd::cross(a - c, p - c), n),
            wc = simd::dot(simd::cross(b - a, p - a), n);
    if (!(wa >= R(0) && wb >= R(0) && wc >= R(0))) return e;
    const R h = simd::dot(p - a, n);
    const Candidate<R> f{h * h / n2, wb / n2, wc / n2};
    return f.dist2 < e.dist2 ? f : e;
}
}  // namespace detail

/// The walk over the Voronoi regions answers in double for proper triangles. Thin ones (a corner
/// angle below ~2^-15; collinear or coincident corners), where its products cancel, take
/// closest_thin in long double (checked against exact rational arithmetic on such a sliver).
inline TrianglePoint closest_on_triangle(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const Vec3d ab = b - a, ac = c - a, n = simd::cross(ab, ac);
    const bool thin = !(simd::dot(n, n) > 0x1p-30 * simd::dot(ab, ab) * simd::dot(ac, ac));
    if (!thin) {
        bool ok = true;
        const detail::Candidate<double> r = detail::closest_by_regions(p, a, b, c, ok);
        if (ok) return {r.dist2, r.u, r.v};
    }
    using L = long double;
    const auto to_l = [](const Vec3d& v) { return simd::Vec3<L>{L(v.x), L(v.y), L(v.z)}; };
    const detail::Candidate<L> r = detail::closest_thin(to_l(p), to_l(a), to_l(b), to_l(c));
    return {double(r.dist2), double(r.u), double(r.v)};
}

/// One closest-point search: the query point, the best candidate so far and the bound that prunes
/// boxes. The rule: a candidate is kept when it is strictly closer, or exactly as close (in double)
/// with a lower triangle number; so every structure, whatever order it visits the triangles in,
/// returns the same record as brute force.
struct PointSearch {
    Vec3f pf;               ///< the query point
    Vec3d p;                ///< the same in double
    double best2;           ///< squared distance of the best candidate, or max_distance^2 before one
    std::uint32_t prim = invalid_prim;
    double u = 0.0, v = 0.0;
    Vec3d q{0.0, 0.0, 0.0};  ///< the best candidate's closest point
    float bound = std::numeric_limits<float>::infinity();  ///< see prune_bound()

    PointSearch(const Vec3f& point, float max_distance)
        : pf(point), p(to_double(point)), best2(double(max_distance) * double(max_distance)) {
        update_bound();
    }

    /// Whether the point can be searched: finite coordinates and a non-negative reach.
    bool searchable() const {
        return std::isfinite(pf.x) && std::isfinite(pf.y) && std::isfinite(pf.z) && best2 >= 0.0;
    }

    /// Offers triangle `id` with corners (a, b, c).
    void offer(const Vec3f& a, const Vec3f& b, const Vec3f& c, std::uint32_t id) {
        const Vec3d da = to_double(a), db = to_double(b), dc = to_double(c);
        const TrianglePoint t = closest_on_triangle(p, da, db, dc);
        if (t.dist2 < best2 || (t.dist2 == best2 && id < prim)) {
            best2 = t.dist2, prim = id, u = t.u, v = t.v;
            q = da * (1.0 - u - v) + db * u + dc * v;
            update_bound();
        }
    }

    /// A box whose float squared distance (simd::point_box_dist2-style: per axis the positive part
    /// of lo - p and p - hi, squared and summed) exceeds this cannot hold a candidate that offer()
    /// would keep. The float sum errs by at most ~6 float roundings (< 4e-7 relative) and can only
    /// underflow towards 0, so the bound is best2 grown by 2e-6 and rounded up to float.
    float prune_bound() const { return bound; }

    /// The result record.
    PointHit result() const {
        PointHit h;
        if (prim == invalid_prim) return h;
        h.distance = float(std::sqrt(best2));
        h.prim = prim;
        h.point = {float(q.x), float(q.y), float(q.z)};
        h.u = float(u), h.v = float(v);
        return h;
    }

private:
    void update_bound() {
        const double grown = best2 * (1.0 + 2e-6);
        const float f = float(grown);
        bound = double(f) >= grown ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
    }
};

/// A reach for the search at `p` that keeps its answer and prunes from the start: the distance
/// from p to `near`, a point of the surface as another search found it (PointHit::point, the exact
/// closest point rounded to float), grown past that rounding (at most 2^-24 of its largest
/// coordinate per axis) and the double sum's; at most `max_distance`. The surface has a point
/// strictly within it, so the search finds the same record as from `max_distance` (offer()'s rule
/// does not depend on what was offered first): a query next to the last one starts nearly done.
inline float warm_reach(const Vec3f& p, const PointHit& near, float max_distance) {
    if (!near.is_hit()) return max_distance;
    const Vec3d q = to_double(near.point), d = to_double(p) - q;
    const double m = std::max(std::fabs(q.x), std::max(std::fabs(q.y), std::fabs(q.z)));
    const double r = std::sqrt(simd::dot(d, d)) * (1.0 + 1e-6) + m * 0x1p-21 + 1e-30;
    if (!(r < double(max_distance))) return max_distance;
    const float f = float(r);
    return double(f) >= r ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
}

/// Squared distance from p to box [lo, hi] per the rule of PointSearch::prune_bound, for T = float
/// or a batch (an empty box, lo = +inf and hi = -inf, is infinitely far).
template <class T>
inline T point_box_dist2(const T& px, const T& py, const T& pz, const T& lox, const T& loy, const T& loz,
                         const T& hix, const T& hiy, const T& hiz) {
    const T zero(0.0f);
    const T dx = simd::rmax(simd::rmax(lox - px, px - hix), zero);
    const T dy = simd::rmax(simd::rmax(loy - py, py - hiy), zero);
    const T dz = simd::rmax(simd::rmax(loz - pz, pz - hiz), zero);
    return dx * dx + dy * dy + dz * dz;
}

/// The float squared distance from p to the box of triangle (a, b, c), as point_box_dist2: a
/// triangle whose box is beyond PointSearch::prune_bound cannot be kept, so its exact test is skipped.
inline float triangle_box_dist2(const Vec3f& p, const Vec3f& a, const Vec3f& b, const Vec3f& c) {
    const Vec3f lo = simd::vmin(simd::vmin(a, b), c), hi = simd::vmax(simd::vmax(a, b), c);
    return point_box_dist2<float>(p.x, p.y, p.z, lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
}

}  // namespace arbor::accel
