#pragma once
/// Conservative ray/box slab test over lane type T. See "Robust BVH Ray Traversal", T. Ize, JCGT 2013:
/// far-plane distances use a reciprocal direction padded by 2 ulps, so rounding can only make a
/// box bigger, never lose a hit (for negative distances, behind the origin, see slab_test).
///
/// The zero-direction rule, shared by every path: rcp = 1/d is +-inf for d = +-0, the near plane of
/// each axis is chosen by the sign bit of d (so -0 behaves as negative), and a slab distance that
/// comes out NaN (0 * inf: the origin lies exactly in the plane) is ignored by rmax/rmin, i.e. the
/// ray counts as inside that slab.
#include "simd/vec3.h"

#include <cmath>

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

/// Per-ray constants of the slab test.
struct SlabRay {
    Vec3f org;
    Vec3f rcp_near;            ///< 1/d
    Vec3f rcp_far;             ///< 1/d padded by 2 ulps
    int near_is_hi[3] = {};    ///< 1 when d has its sign bit set: the near plane is the box's max
};

inline SlabRay slab_ray(const Vec3f& o, const Vec3f& d) {
    SlabRay r;
    r.org = o;
    for (int k = 0; k < 3; ++k) {
        r.rcp_near[k] = 1.0f / d[k];
        r.rcp_far[k] = pad_2ulp(r.rcp_near[k]);
        r.near_is_hi[k] = std::signbit(d[k]) ? 1 : 0;
    }
    return r;
}

/// The acceptance rule of slab_test: entry <= exit, with room for negative exits. The padded
/// reciprocal widens [entry, exit] only where distances are positive. A box behind the origin
/// (reachable when tnear < 0) has a negative exit, which the padding moves towards the entry: a flat
/// box there would be lost. Negative exits get 2^-20 (16 ulps) of room back. Monotone in t_exit
/// (packet_bounds.h relies on it: a larger exit never turns a hit into a miss).
template <class T> inline Mask<T> slab_accept(const T& t_entry, const T& t_exit) {
    const T slack = rmin(t_exit, T(0.0f)) * T(-0x1p-20f);
    return t_entry <= t_exit + slack;
}

/// Slab test on planes already sorted into near and far per axis. Returns the entry distance in
/// `t_entry` and the lanes whose [entry, exit] overlaps [tnear, tfar].
template <class T>
inline Mask<T> slab_test(const Vec3<T>& near_plane, const Vec3<T>& far_plane, const Vec3<T>& org,
                         const Vec3<T>& rcp_near, const Vec3<T>& rcp_far, const T& tnear, const T& tfar,
                         T& t_entry) {
    const T n0 = (near_plane.x - org.x) * rcp_near.x;
    const T n1 = (near_plane.y - org.y) * rcp_near.y;
    const T n2 = (near_plane.z - org.z) * rcp_near.z;
    const T f0 = (far_plane.x - org.x) * rcp_far.x;
    const T f1 = (far_plane.y - org.y) * rcp_far.y;
    const T f2 = (far_plane.z - org.z) * rcp_far.z;
    t_entry = rmax(n0, rmax(n1, rmax(n2, tnear)));
    const T t_exit = rmin(f0, rmin(f1, rmin(f2, tfar)));
    return slab_accept(t_entry, t_exit);
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
