#pragma once
/// Conservative ray/box slab test over lane type T. See "Robust BVH Ray Traversal", T. Ize, JCGT 2013:
/// far-plane distances use a reciprocal direction padded by 2 ulps, so rounding can only make a
/// box bigger, never lose a hit (for negative distances, behind the origin, see slab_test).
///
/// The zero-direction rule, shared by every path: rcp = 1/d is +-inf for d = +-0, the near plane of
/// each axis is chosen by the sign bit of d (so -0 behaves as negative), and a slab distance that
/// comes out NaN (0 * inf: the origin lies exactly in the plane) is ignored by rmax/rmin, i.e. the
/// ray counts as inside that slab; when both planes of a slab of no thickness give NaN, the box is
/// culled (in_flat_slab: it holds only triangles coplanar with the ray, which the triangle test misses).
#include "simd/vec3.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>
#include <type_traits>

namespace arbor::simd {

/// |x| increased by two ulps (inf stays inf, NaN stays NaN, +-0 becomes +-2 denorm_min).
inline float pad_2ulp(float x) {
    const float toward = std::signbit(x) ? -INFINITY : INFINITY;
    return std::nextafter(std::nextafter(x, toward), toward);
}

/// The same per lane, by integer arithmetic on the bit pattern: adding 2 to the magnitude bits is
/// two nextafter steps away from zero (across the denormal range too), clamped at infinity; NaN
/// stays NaN. Bit-identical to the scalar form (tested lane by lane).
template <class A> inline xsimd::batch<float, A> pad_2ulp(const xsimd::batch<float, A>& x) {
    using I = xsimd::batch<std::int32_t, A>;
    const I bits = xsimd::bitwise_cast<I>(x);
    const I mag = bits & I(0x7fffffff);
    const I inf(0x7f800000), up = mag + I(2);  // wraps for NaN patterns near 0x7fffffff: replaced below
    const I padded = xsimd::select(up > inf, inf, up) | (bits & I(std::int32_t(0x80000000u)));
    return xsimd::bitwise_cast<xsimd::batch<float, A>>(xsimd::select(mag > inf, bits, padded));
}

/// 1/d[k] for the slab test, on the ray the triangle test sees. The watertight test shears by
/// d[k] / d[kz] (ray_triangle.h), with |d[kz]| = dmax, the largest |d| component:
/// - when that ratio underflows to 0, the triangle test sees a ray that does not move along k, so
///   the box test does too: the zero-direction rule (+-inf, by the sign of d[k]);
/// - when it is denormal (imprecise), or 1/d[k] overflows, the two tests could place the ray
///   differently along k: NaN, so that axis never culls (a NaN distance is ignored by rmax/rmin,
///   as for an origin lying in a slab plane). Only near-axis directions with components below
///   FLT_MIN * dmax are affected. Found by arbor's fuzzer (tests/fuzz/regressions/rays).
/// - when 1/d[k] is denormal (|d[k]| > 2^126), it carries as few as 21 bits: its rounding error
///   (up to 2^-22 relative) exceeds the 2-ulp padding of another axis's exit (2^-23), which Ize's
///   bound relies on, and a ray grazing a flat box lost its hit. The reciprocal is then shrunk by
///   two ulps towards zero, below 1/d[k] (3 * 2^-24 relative at least), so the entry distances it
///   gives never exceed the exact ones; slab_far (below) pads it by four, back above 1/d[k]. Not
///   NaN: on a ray whose every axis is NaN, empty boxes would pass. Found by arbor's fuzzer
///   (tests/fuzz/regressions/obj/huge-direction-*.obj).
inline float slab_rcp(float d, float dmax) {
    const float r = 1.0f / d;
    if (d == 0.0f) return r;
    const float q = std::fabs(d) / dmax;
    if (q == 0.0f) return d < 0.0f ? -std::numeric_limits<float>::infinity() : std::numeric_limits<float>::infinity();
    if (q < std::numeric_limits<float>::min() || std::isinf(r)) return std::numeric_limits<float>::quiet_NaN();
    return std::fabs(r) < std::numeric_limits<float>::min() ? std::bit_cast<float>(std::bit_cast<std::uint32_t>(r) - 2u) : r;
}
template <class A>
inline xsimd::batch<float, A> slab_rcp(const xsimd::batch<float, A>& d, const xsimd::batch<float, A>& dmax) {
    using B = xsimd::batch<float, A>;
    using I = xsimd::batch<std::int32_t, A>;
    const B inf(std::numeric_limits<float>::infinity()), zero(0.0f), fmin(std::numeric_limits<float>::min());
    const B r = B(1.0f) / d, q = xsimd::abs(d) / dmax;
    const auto moving = d != zero;
    const B rule = xsimd::select(d < zero, -inf, inf);
    const B nan(std::numeric_limits<float>::quiet_NaN());
    const auto unsure = moving & (q != zero) & ((q < fmin) | (xsimd::abs(r) == inf));
    // (|r| >= 2^-128 here, so its magnitude bits minus 2 stay positive: the sign is kept.)
    const B shrunk = xsimd::bitwise_cast<B>(xsimd::bitwise_cast<I>(r) - I(2));
    const B sure = xsimd::select(xsimd::abs(r) < fmin, shrunk, r);
    return xsimd::select(moving & (q == zero), rule, xsimd::select(unsure, nan, sure));
}

/// slab_rcp of each component of d, dmax = the largest |d[k]|.
template <class T> inline Vec3<T> slab_rcp_each(const Vec3<T>& d, const T& dmax) {
    return {slab_rcp(d.x, dmax), slab_rcp(d.y, dmax), slab_rcp(d.z, dmax)};
}

/// slab_rcp_each, bit for bit, with fewer divisions in most packets. The quotient |d[k]| / dmax only
/// decides for a component below 2^-64 dmax (zero, denormal or normal but tiny: near-axis
/// directions): when every lane's components are zero or at least that (any camera or shadow
/// ray), it is left out, and with it three of the six divisions of a packet's set-up (|d| * 2^64
/// is exact or +inf, so |d| * 2^64 >= dmax means q >= 2^-64 > FLT_MIN: the q == 0 and q < FLT_MIN
/// cases cannot occur). Bit-identical to slab_rcp per component (tested lane by lane).
template <class T> inline Vec3<T> slab_rcps(const Vec3<T>& d, const T& dmax) {
    if constexpr (std::is_same_v<T, float>) {
        return slab_rcp_each(d, dmax);
    } else {
        using I = xsimd::batch<std::int32_t, typename T::arch_type>;
        const T zero(0.0f), big(0x1p64f), inf(std::numeric_limits<float>::infinity());
        const T fmin(std::numeric_limits<float>::min()), nan(std::numeric_limits<float>::quiet_NaN());
        auto sure_q = (xsimd::abs(d.x) * big >= dmax) | !(d.x != zero);
        sure_q = sure_q & ((xsimd::abs(d.y) * big >= dmax) | !(d.y != zero));
        sure_q = sure_q & ((xsimd::abs(d.z) * big >= dmax) | !(d.z != zero));
        if (!xsimd::all(sure_q)) return slab_rcp_each(d, dmax);
        Vec3<T> out;
        for (int k = 0; k < 3; ++k) {
            // slab_rcp with q >= 2^-64 wherever d[k] != 0: no zero rule, NaN only where 1/d overflows.
            const T r = T(1.0f) / d[k];
            const T shrunk = xsimd::bitwise_cast<T>(xsimd::bitwise_cast<I>(r) - I(2));
            const T sure = xsimd::select(xsimd::abs(r) < fmin, shrunk, r);
            out[k] = xsimd::select((d[k] != zero) & (xsimd::abs(r) == inf), nan, sure);
        }
        return out;
    }
}

/// The far-plane reciprocal from slab_rcp's: padded by 2 ulps (Ize), by 4 when it is denormal
/// (slab_rcp shrank it by 2: the padding is then 2 ulps above the rounded 1/d, as on a normal
/// axis). Monotone on slab_rcp's values (its denormals are at most FLT_MIN minus 3 ulps, so
/// padded by 4 they stay below FLT_MIN padded by 2): packet_bounds.h relies on it.
inline float slab_far(float rcp) {
    const float p = pad_2ulp(rcp);
    return std::fabs(rcp) < std::numeric_limits<float>::min() && rcp != 0.0f ? pad_2ulp(p) : p;
}
/// (Per lane, as pad_2ulp's batch form, with the step 4 on non-zero denormals: one pass.)
template <class A> inline xsimd::batch<float, A> slab_far(const xsimd::batch<float, A>& rcp) {
    using I = xsimd::batch<std::int32_t, A>;
    const I bits = xsimd::bitwise_cast<I>(rcp);
    const I mag = bits & I(0x7fffffff);
    const I inf(0x7f800000);
    const I up = mag + xsimd::select((mag < I(0x00800000)) & (mag != I(0)), I(4), I(2));
    const I padded = xsimd::select(up > inf, inf, up) | (bits & I(std::int32_t(0x80000000u)));
    return xsimd::bitwise_cast<xsimd::batch<float, A>>(xsimd::select(mag > inf, bits, padded));
}

/// Per-ray constants of the slab test.
struct SlabRay {
    Vec3f org;
    Vec3f rcp_near;            ///< 1/d
    Vec3f rcp_far;             ///< 1/d padded by 2 ulps (slab_far)
    int near_is_hi[3] = {};    ///< 1 when d has its sign bit set: the near plane is the box's max
};

inline SlabRay slab_ray(const Vec3f& o, const Vec3f& d) {
    SlabRay r;
    r.org = o;
    const float dmax = std::max(std::fabs(d.x), std::max(std::fabs(d.y), std::fabs(d.z)));
    for (int k = 0; k < 3; ++k) {
        r.rcp_near[k] = slab_rcp(d[k], dmax);
        r.rcp_far[k] = slab_far(r.rcp_near[k]);
        r.near_is_hi[k] = std::signbit(d[k]) ? 1 : 0;
    }
    return r;
}

/// The acceptance rule of slab_test: entry <= exit, with room for negative exits. The padded
/// reciprocal widens [entry, exit] only where distances are positive. A box behind the origin
/// (reachable when tnear < 0) has a negative exit, which the padding moves towards the entry: a flat
/// box there would be lost. Negative exits get 2^-17 (128 ulps) of room back: the far reciprocal
/// exceeds the near one by 2 ulps of a normal 1/d (2^-22..2^-23 relative) and by 6 ulps of a
/// denormal one (slab_rcp, slab_far: up to 6 * 2^-149 / 2^-128 < 2^-18 relative, for |d| up to
/// FLT_MAX), plus the rounding of the subtraction and product. (It was 2^-20, which the denormal
/// reciprocals' 6-ulp gap exceeded: a box behind the origin of a ray with |d.x| = 2.4e38 and
/// tnear < 0, 3.7e10 from the scene, so that the box's planes minus the origin round to one value,
/// was culled; found by CI's ray fuzzer, tests/fuzz/regressions/rays/huge-direction-behind-origin-far.rays.)
/// Monotone in t_exit (packet_bounds.h relies on it: a larger exit never turns a hit into a miss).
/// The largest entry slab_accept takes for `t_exit` (for callers that compare many entries with one exit).
template <class T> inline T slab_accept_bound(const T& t_exit) { return t_exit + rmin(t_exit, T(0.0f)) * T(-0x1p-17f); }
template <class T> inline Mask<T> slab_accept(const T& t_entry, const T& t_exit) { return t_entry <= slab_accept_bound(t_exit); }

/// The far distance a closest-hit walk tests boxes against while its closest hit so far (or the
/// ray's own tfar) is at t: t raised by 2^-18 of itself, t * (1 + 2^-18) (negative t as it is:
/// slab_accept's room covers it). The triangle tests keep t itself, so no answer can get farther;
/// only culling changes. Why: a ray through a vertex (or along a flat box's face) meets the box of
/// a triangle there exactly at that triangle's hit point, and the two computed distances round
/// apart. The entry, (plane - org) * (1/d), is off by up to 3 roundings (3 * 2^-24 relative); the
/// triangle's t, a convex combination of its corners' sheared distances divided by det
/// (ray_triangle.h), by about 10 more where the corners lie on one side of the origin, and its
/// point moves with the sheared frame by a few ulps of the distance travelled (~2^-21.4, the bound
/// the kd-tree's point_tolerance, kdtree_traverse.h, takes 2^-18 for): together about 2^-19.5, so
/// 2^-18 leaves a margin of ~3. Without it the nearer of two triangles meeting at a vertex could
/// round below its box's entry while the other one's t, an ulp or a few above it, became tfar: the
/// box was culled and the farther triangle returned (tests/test_vertex_aimed.cpp). One multiply
/// and one max (on the chain from a leaf's hit to the next pop); recomputed only when a leaf
/// lowers tfar. inf stays inf, NaN stays NaN; monotone in t.
template <class T>
inline T box_tfar(const T& t) {
    return rmax(t * T(1.0f + 0x1p-18f), t);
}

/// The flat-slab rule (lanes where it holds are culled by slab_test): on an axis the ray does not
/// move along (reciprocal +-inf by slab_rcp's zero-direction rule), a box of no thickness whose
/// plane holds the origin gives NaN for both its slab distances (0 * inf). Every triangle in that
/// box lies in that plane, and so does the ray: the watertight test sees all three of its edge
/// functions exactly 0 (the triangle's coordinates along the axis minus the origin's are exactly 0,
/// and the shear along it is 0), so its determinant is 0 and it misses. Culling such boxes changes
/// no answer, and rays lying in the plane of a flat mesh no longer walk every box along their line.
/// A NaN reciprocal (slab_rcp's unsure axis) never culls; nor does a box with thickness whose face
/// holds the origin (one NaN distance: triangles crossing that plane can be hit on their edges).
template <class T> inline Mask<T> in_flat_slab(const Vec3<T>& n, const Vec3<T>& f, const Vec3<T>& rcp_near) {
    const T inf(std::numeric_limits<float>::infinity());
    // NaN as !(x == x) on batches: xsimd's != is an ordered compare on some targets (false for NaN).
    const auto nan = [](const T& x) -> Mask<T> {
        if constexpr (std::is_same_v<T, float>) return std::isnan(x);
        else return !(x == x);
    };
    const auto flat_axis = [&](int k) -> Mask<T> { return nan(n[k]) && nan(f[k]) && vabs(rcp_near[k]) == inf; };
    if constexpr (std::is_same_v<T, float>) {
        return flat_axis(0) || flat_axis(1) || flat_axis(2);
    } else {
        return flat_axis(0) | flat_axis(1) | flat_axis(2);
    }
}

/// Slab test on planes already sorted into near and far per axis. Returns the entry distance in
/// `t_entry` and the lanes whose [entry, exit] overlaps [tnear, tfar].
template <class T>
inline Mask<T> slab_test(const Vec3<T>& near_plane, const Vec3<T>& far_plane, const Vec3<T>& org,
                         const Vec3<T>& rcp_near, const Vec3<T>& rcp_far, const T& tnear, const T& tfar,
                         T& t_entry) {
    const Vec3<T> n = (near_plane - org) * rcp_near, f = (far_plane - org) * rcp_far;
    t_entry = rmax(n.x, rmax(n.y, rmax(n.z, tnear)));
    const T t_exit = rmin(f.x, rmin(f.y, rmin(f.z, tfar)));
    if constexpr (std::is_same_v<T, float>) {
        return slab_accept(t_entry, t_exit) && !in_flat_slab(n, f, rcp_near);
    } else {
        return slab_accept(t_entry, t_exit) & !in_flat_slab(n, f, rcp_near);
    }
}

/// Whether a ray (per lane) is "plain": tnear >= 0 and all six reciprocals finite and normal (no
/// zero or near-axis component). For such rays slab_test_plain gives slab_test's answer in fewer
/// dependent steps. (Traceability is the caller's to add.)
template <class T> inline Mask<T> is_plain(const T& tnear, const Vec3<T>& rcp_near, const Vec3<T>& rcp_far) {
    Mask<T> plain = tnear >= T(0.0f);
    for (int k = 0; k < 3; ++k)
        plain = plain & (vabs(rcp_near[k]) >= T(std::numeric_limits<float>::min())) &
                (vabs(rcp_far[k]) <= T(std::numeric_limits<float>::max()));
    return plain;
}

/// slab_test for plain rays (is_plain): the same hits, and entry distances equal as numbers (a zero
/// may differ in sign). Why it is the same test:
///   - no slab distance can be NaN: a plane minus the origin is finite or +-inf (the empty slots),
///     and times a finite non-zero reciprocal stays non-NaN; so the NaN-ignoring folds of slab_test
///     are plain max/min and can be taken as a tree (two steps instead of three);
///   - slab_accept is the plain comparison t_entry <= t_exit: t_entry >= tnear >= 0, so when
///     t_exit >= 0 the slack is zero, and when t_exit < 0, t_exit plus its slack (2^-17 of it)
///     stays negative and both forms reject.
/// Per node that takes the slack's three steps and two fold steps off the chain from a node's loads
/// to the next node's address.
template <class T>
ARBOR_INLINE Mask<T> slab_test_plain(const Vec3<T>& near_plane, const Vec3<T>& far_plane, const Vec3<T>& org,
                                     const Vec3<T>& rcp_near, const Vec3<T>& rcp_far, const T& tnear, const T& tfar,
                                     T& t_entry) {
    const Vec3<T> n = (near_plane - org) * rcp_near, f = (far_plane - org) * rcp_far;
    t_entry = rmax(rmax(n.x, n.y), rmax(n.z, tnear));
    const T t_exit = rmin(rmin(f.x, f.y), rmin(f.z, tfar));
    return t_entry <= t_exit;
}

/// Scalar form on an axis-aligned box [lo, hi].
inline bool slab_test(const SlabRay& r, const Vec3f& lo, const Vec3f& hi, float tnear, float tfar, float& t_entry) {
    Vec3f n, f;
    for (int k = 0; k < 3; ++k) {
        n[k] = r.near_is_hi[k] ? hi[k] : lo[k];
        f[k] = r.near_is_hi[k] ? lo[k] : hi[k];
    }
    return slab_test<float>(n, f, r.org, r.rcp_near, r.rcp_far, tnear, tfar, t_entry);
}

}  // namespace arbor::simd
