#pragma once
/// Ray/triangle kernels over the lane type T, all built on the one woop_permuted template of
/// tri_test.h (the same math, the same double-precision fallback per lane, the same watertight
/// guarantee as the scalar oracle):
///   - packet_triangle:       a RayPacket against one triangle; each lane has its own Woop
///                            permutation, applied with selects unless all active lanes share one;
///   - packet_triangle_lanes: the same, always with per-lane selects (for tests and benchmarks);
///   - ray_triangles:         one WideRay against lanes<T> triangles in SoA form (a leaf block).
#include "simd/ray_packet.h"
#include "simd/wide_ray.h"

#include <cstddef>

namespace arbor::simd {

/// lanes<T> triangles in SoA form: v[vertex][axis][lane]. The vertices are stored, not edges: the
/// watertight test needs each vertex translated on its own. Unused slots must hold NaN vertices
/// (they never hit and never reach the double-precision fallback, unlike zero-area padding).
template <std::size_t N> struct TrisSoA {
    alignas(N * sizeof(float) >= 64 ? 64 : N * sizeof(float)) float v[3][3][N];

    void set(std::size_t i, const Vec3f& v0, const Vec3f& v1, const Vec3f& v2) {
        for (int k = 0; k < 3; ++k) {
            v[0][k][i] = v0[k];
            v[1][k][i] = v1[k];
            v[2][k][i] = v2[k];
        }
    }
    void set_empty(std::size_t i) { set(i, Vec3f(NAN), Vec3f(NAN), Vec3f(NAN)); }
};

namespace detail {
template <class T, bool PerLane>
inline TriHit<T> packet_triangle_impl(const RayPacket<T>& p, const Vec3f& v0, const Vec3f& v1, const Vec3f& v2) {
    const auto rel = [&p](const Vec3f& v) { return Vec3<T>{T(v.x), T(v.y), T(v.z)} - p.org; };
    const auto perm = [&p](const Vec3<T>& v) {
        if constexpr (PerLane) return permute_lanes(p.woop, v);
        else return permute_uniform(p.woop, v);
    };
    TriHit<T> h = woop_permuted<T>(perm(rel(v0)), perm(rel(v1)), perm(rel(v2)), p.woop.sx, p.woop.sy, p.woop.sz,
                                   p.tnear, p.tfar);
    h.hit = h.hit & p.active;
    return h;
}
}  // namespace detail

/// A packet against triangle (v0, v1, v2). Per lane: hit, t and barycentrics (u weights v1, v
/// weights v2), bit-identical to the scalar woop_test of that lane's ray. Inactive lanes never hit.
template <class T>
inline TriHit<T> packet_triangle(const RayPacket<T>& p, const Vec3f& v0, const Vec3f& v1, const Vec3f& v2) {
    if (p.woop.uniform) return detail::packet_triangle_impl<T, false>(p, v0, v1, v2);
    return detail::packet_triangle_impl<T, true>(p, v0, v1, v2);
}
template <class T>
inline TriHit<T> packet_triangle_lanes(const RayPacket<T>& p, const Vec3f& v0, const Vec3f& v1, const Vec3f& v2) {
    return detail::packet_triangle_impl<T, true>(p, v0, v1, v2);
}

/// One ray against lanes<T> triangles given as vertices in x, y, z order.
template <class T>
inline TriHit<T> ray_triangles(const WideRay<T>& r, const Vec3<T>& v0, const Vec3<T>& v1, const Vec3<T>& v2) {
    const auto rel = [&r](const Vec3<T>& v) { return Vec3<T>{v[r.kx], v[r.ky], v[r.kz]} - r.org_perm; };
    return woop_permuted<T>(rel(v0), rel(v1), rel(v2), r.sx, r.sy, r.sz, r.tnear, r.tfar);
}

/// One ray against lanes<T> triangles stored as TrisSoA<lanes<T>> (`soa` points at its v[0][0][0]):
/// only the three axes the ray's permutation needs are loaded, already in (kx, ky, kz) order.
template <class T> inline TriHit<T> ray_triangles(const WideRay<T>& r, const float* soa) {
    constexpr std::size_t n = lanes<T>;
    const auto rel = [&r, soa](std::size_t vertex) {
        const float* v = soa + vertex * 3 * n;
        return Vec3<T>{load_lanes<T>(v + std::size_t(r.kx) * n), load_lanes<T>(v + std::size_t(r.ky) * n),
                       load_lanes<T>(v + std::size_t(r.kz) * n)} -
               r.org_perm;
    };
    return woop_permuted<T>(rel(0), rel(1), rel(2), r.sx, r.sy, r.sz, r.tnear, r.tfar);
}
template <class T, std::size_t N> inline TriHit<T> ray_triangles(const WideRay<T>& r, const TrisSoA<N>& tris) {
    static_assert(N == lanes<T>, "one lane per triangle");
    return ray_triangles(r, &tris.v[0][0][0]);
}

}  // namespace arbor::simd
