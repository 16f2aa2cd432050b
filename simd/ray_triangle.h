#pragma once
/// Watertight ray/triangle test, written once over the lane type T (float or an xsimd batch).
/// See "Watertight Ray/Triangle Intersection", S. Woop, C. Benthin, I. Wald, JCGT 2013.
///
/// Why it is watertight: every vertex is moved into the ray's sheared frame on its own, so a vertex
/// gets the same 2-D coordinates in every triangle that uses it. The edge function
/// U = cx*by - cy*bx is then an orientation test of two such points; float rounding is monotone,
/// so its sign is either exact or 0, and a 0 is settled exactly in double precision (products of
/// floats are exact in double). Two triangles sharing an edge therefore see exactly opposite
/// signs. This needs a*b - c*d to be rounded twice: the build uses -ffp-contract=off.
///
/// Ties (an edge function exactly 0: the ray passes exactly through an edge or a vertex as the
/// test sees them) are decided as if the ray's point in the sheared frame were moved by an
/// infinitesimal step (e, e*h), 0 < h << 1, the same for every triangle (symbolic perturbation, as
/// rasterizers' top-left rule): the zero edge function of an edge p -> q then takes the sign of
/// q.y - p.y, or of p.x - q.x when q.y == p.y, and the triangle is hit only when that sign is the
/// sign of its other, non-zero edge functions (of det). The moved point lies on no edge line, so a
/// ray through an edge shared by two triangles that it crosses hits exactly one of them, one it
/// grazes (a silhouette: the two project onto the same side) both or neither, and a ray through a
/// vertex hits exactly one triangle of a fan it crosses. A closed, consistently oriented mesh is
/// therefore crossed an even number of times by a ray from outside, also through its edges and
/// vertices. Away from ties nothing changes, and an accepted tie keeps its t, u and v.
#include "simd/vec3.h"

#include <cfloat>
#include <limits>

namespace arbor::simd {

/// Per-ray constants of the test: axis permutation (kz = dominant axis) and shear.
struct WoopShear {
    int kx = 0, ky = 1, kz = 2;
    float sx = 0, sy = 0, sz = 1;
};

/// Shear for direction d (must be finite and non-zero). The permutation keeps the winding:
/// kx, ky are swapped when d[kz] is negative.
inline WoopShear woop_shear(const Vec3f& d) {
    WoopShear s;
    const Vec3f a{std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)};
    s.kz = max_axis(a);
    s.kx = (s.kz + 1) % 3;
    s.ky = (s.kx + 1) % 3;
    if (std::signbit(d[s.kz])) std::swap(s.kx, s.ky);
    s.sx = d[s.kx] / d[s.kz];
    s.sy = d[s.ky] / d[s.kz];
    s.sz = 1.0f / d[s.kz];
    return s;
}

template <class T> struct TriHit {
    Mask<T> hit;
    T t, u, v;  ///< valid in lanes where hit; u weights v1, v weights v2
};

namespace detail {
/// Settle a zero edge function exactly: recompute a*b - c*d in double (exact products, one
/// rounding) and keep its sign even when the value is below float range.
inline float edge_exact(float ax, float by, float ay, float bx) {
    const double d = double(ax) * double(by) - double(ay) * double(bx);
    if (d == 0.0) return 0.0f;
    const float f = float(d);
    return f != 0.0f ? f : std::copysign(FLT_MIN, float(d > 0 ? 1 : -1));
}
/// The sign (+1, -1; 0 for a zero-length edge) that the zero edge function of edge p -> q takes
/// when the ray's point moves by (e, e*h): see the header comment.
inline float tie_sign(float px, float py, float qx, float qy) {
    if (qy != py) return qy > py ? 1.0f : -1.0f;
    if (qx != px) return qx < px ? 1.0f : -1.0f;
    return 0.0f;
}
/// Settles the edge functions exactly (some float one is 0), then applies the tie rule: a zero
/// edge function whose tie_sign is not the sign of the non-zero ones is set to the opposite sign
/// (a miss); one that agrees stays 0, so the hit's t, u and v are those of the test without the
/// rule. U belongs to edge b -> c, V to c -> a, W to a -> b. Out of line and cold: it is rare, and
/// inlined its size made GCC 12 call woop_test in the scalar walks and add_woop and wide_ray_setup
/// in the wide paths instead of inlining them.
[[gnu::cold, gnu::noinline]] inline void settle_edges(float& U, float& V, float& W, float ax, float ay, float bx,
                                                      float by, float cx, float cy) {
    U = edge_exact(cx, by, cy, bx);
    V = edge_exact(ax, cy, ay, cx);
    W = edge_exact(bx, ay, by, ax);
    const bool pos = U > 0.0f || V > 0.0f || W > 0.0f, neg = U < 0.0f || V < 0.0f || W < 0.0f;
    if (pos == neg) return;  // mixed signs (a miss), or all three 0 (det == 0: a miss)
    const float s = pos ? 1.0f : -1.0f;
    if (U == 0.0f && tie_sign(bx, by, cx, cy) != s) U = -s;
    if (V == 0.0f && tie_sign(cx, cy, ax, ay) != s) V = -s;
    if (W == 0.0f && tie_sign(ax, ay, bx, by) != s) W = -s;
}
inline void refine_edges(float& U, float& V, float& W, float ax, float ay, float bx, float by, float cx, float cy) {
    if (U == 0.0f || V == 0.0f || W == 0.0f) settle_edges(U, V, W, ax, ay, bx, by, cx, cy);
}
template <class A>  // (forced inline: as push_ordered16, accel/wide/wide_push.h)
ARBOR_INLINE void refine_edges(xsimd::batch<float, A>& U, xsimd::batch<float, A>& V, xsimd::batch<float, A>& W,
                               const xsimd::batch<float, A>& ax, const xsimd::batch<float, A>& ay,
                               const xsimd::batch<float, A>& bx, const xsimd::batch<float, A>& by,
                               const xsimd::batch<float, A>& cx, const xsimd::batch<float, A>& cy) {
    using B = xsimd::batch<float, A>;
    const auto zero = (U == B(0.0f)) | (V == B(0.0f)) | (W == B(0.0f));
    std::uint32_t bits = to_bits(zero);
    if (bits == 0) return;
    alignas(64) float u[B::size], v[B::size], w[B::size], a0[B::size], a1[B::size], b0[B::size], b1[B::size],
        c0[B::size], c1[B::size];
    U.store_aligned(u); V.store_aligned(v); W.store_aligned(w);
    ax.store_aligned(a0); ay.store_aligned(a1); bx.store_aligned(b0); by.store_aligned(b1);
    cx.store_aligned(c0); cy.store_aligned(c1);
    while (bits) {
        const int i = std::countr_zero(bits);
        bits &= bits - 1;
        settle_edges(u[i], v[i], w[i], a0[i], a1[i], b0[i], b1[i], c0[i], c1[i]);
    }
    U = B::load_aligned(u); V = B::load_aligned(v); W = B::load_aligned(w);
}
}  // namespace detail

/// The test on vertices already taken relative to the ray origin and permuted into the ray's
/// (kx, ky, kz) frame (so .z is the dominant axis). Accepts t in [tnear, tfar]; a hit exactly on
/// an edge or vertex counts when the tie rule (header comment) gives it to this triangle.
/// Degenerate triangles (det == 0) and NaN results never hit. EarlyOut: when no lane can hit,
/// return before the division with t = u = v = 0 (the hits are the same).
template <class T, bool EarlyOut = false>
ARBOR_INLINE TriHit<T> woop_permuted(const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c, const T& sx, const T& sy,
                               const T& sz, const T& tnear, const T& tfar) {
    const T ax = a.x - sx * a.z, ay = a.y - sy * a.z;
    const T bx = b.x - sx * b.z, by = b.y - sy * b.z;
    const T cx = c.x - sx * c.z, cy = c.y - sy * c.z;
    T U = cx * by - cy * bx;
    T V = ax * cy - ay * cx;
    T W = bx * ay - by * ax;
    detail::refine_edges(U, V, W, ax, ay, bx, by, cx, cy);
    const T zero(0.0f);
    const auto negative = (U < zero) | (V < zero) | (W < zero);
    const auto positive = (U > zero) | (V > zero) | (W > zero);
    const T det = U + V + W;
    if constexpr (EarlyOut) {
        // Every lane misses by its edge signs, or has a NaN det (so a NaN t): skip the division and
        // the rest; the returned t, u, v are zeros, never read where no lane hits.
        if (all((negative & positive) | !(det == det))) {
            TriHit<T> none;
            none.hit = negative & !negative;
            none.t = none.u = none.v = zero;
            return none;
        }
    }
    const T Tv = U * (sz * a.z) + V * (sz * b.z) + W * (sz * c.z);
    const T rcp = T(1.0f) / det;
    TriHit<T> r;
    r.t = Tv * rcp;
    r.u = V * rcp;
    r.v = W * rcp;
    // A NaN t (det == 0, or overflow) fails both comparisons, so it never hits; nor does a t that
    // overflowed to +-inf (a tiny direction, a far triangle): +inf is the miss record's t.
    const T infinity(std::numeric_limits<float>::infinity());
    r.hit = (!(negative & positive)) & (det != zero) & (r.t >= tnear) & (r.t <= tfar) & (r.t < infinity) &
            (r.t > -infinity);
    return r;
}

/// Scalar convenience form: one ray (origin o, shear s) against triangle (v0, v1, v2).
inline TriHit<float> woop_test(const Vec3f& o, const WoopShear& s, float tnear, float tfar, const Vec3f& v0,
                               const Vec3f& v1, const Vec3f& v2) {
    const Vec3f a = v0 - o, b = v1 - o, c = v2 - o;
    return woop_permuted<float>({a[s.kx], a[s.ky], a[s.kz]}, {b[s.kx], b[s.ky], b[s.kz]},
                                {c[s.kx], c[s.ky], c[s.kz]}, s.sx, s.sy, s.sz, tnear, tfar);
}

}  // namespace arbor::simd
