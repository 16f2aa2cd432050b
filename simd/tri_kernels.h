#pragma once
/// Ray/triangle kernels over the lane type T, all built on the one woop_permuted template of
/// ray_triangle.h (the same math, the same double-precision fallback per lane, the same watertight
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
/// The vertices relative to each lane's origin, in each lane's (kx, ky, kz) order: by selects, or
/// by plain component picks when `uniform` (all active lanes share p.woop's permutation).
template <class T>
ARBOR_INLINE void packet_vertices(const RayPacket<T>& p, bool uniform, const Vec3f& v0, const Vec3f& v1, const Vec3f& v2,
                            Vec3<T>& a, Vec3<T>& b, Vec3<T>& c) {
    a = Vec3<T>{T(v0.x), T(v0.y), T(v0.z)} - p.org;
    b = Vec3<T>{T(v1.x), T(v1.y), T(v1.z)} - p.org;
    c = Vec3<T>{T(v2.x), T(v2.y), T(v2.z)} - p.org;
    if (uniform) {
        a = permute_uniform(p.woop, a);
        b = permute_uniform(p.woop, b);
        c = permute_uniform(p.woop, c);
    } else {
        a = permute_lanes(p.woop, a);
        b = permute_lanes(p.woop, b);
        c = permute_lanes(p.woop, c);
    }
}
template <class T, bool EarlyOut = false>
ARBOR_INLINE TriHit<T> packet_triangle_impl(const RayPacket<T>& p, bool uniform, const T& tfar, const Vec3f& v0,
                                            const Vec3f& v1, const Vec3f& v2) {
    Vec3<T> a, b, c;
    packet_vertices(p, uniform, v0, v1, v2, a, b, c);
    // One copy of the test for both permutation paths (two inlined copies measured up to 1.7x slower).
    TriHit<T> h = woop_permuted<T, EarlyOut>(a, b, c, p.woop.sx, p.woop.sy, p.woop.sz, p.tnear, tfar);
    h.hit = h.hit & p.active;
    return h;
}
}  // namespace detail

/// A packet against triangle (v0, v1, v2). Per lane: hit, t and barycentrics (u weights v1, v
/// weights v2), bit-identical to the scalar woop_test of that lane's ray. Inactive lanes never hit.
template <class T>
ARBOR_INLINE TriHit<T> packet_triangle(const RayPacket<T>& p, const Vec3f& v0, const Vec3f& v1, const Vec3f& v2) {
    return detail::packet_triangle_impl(p, p.woop.uniform, p.tfar, v0, v1, v2);
}
/// The same with the lanes' far distances `tfar` in place of p.tfar: for a caller that keeps them
/// in a local while it tests a leaf (each lane then as packet_triangle with p.tfar = tfar).
/// EarlyOut: as ray_triangles' (woop_permuted: no division when no lane can hit).
template <class T, bool EarlyOut = false>
ARBOR_INLINE TriHit<T> packet_triangle(const RayPacket<T>& p, const T& tfar, const Vec3f& v0, const Vec3f& v1,
                                       const Vec3f& v2) {
    return detail::packet_triangle_impl<T, EarlyOut>(p, p.woop.uniform, tfar, v0, v1, v2);
}
template <class T>
inline TriHit<T> packet_triangle_lanes(const RayPacket<T>& p, const Vec3f& v0, const Vec3f& v1, const Vec3f& v2) {
    return detail::packet_triangle_impl(p, false, p.tfar, v0, v1, v2);
}

/// One ray against lanes<T> triangles given as vertices in x, y, z order.
template <class T>
inline TriHit<T> ray_triangles(const WideRay<T>& r, const Vec3<T>& v0, const Vec3<T>& v1, const Vec3<T>& v2) {
    const auto rel = [&r](const Vec3<T>& v) { return Vec3<T>{v[r.kx], v[r.ky], v[r.kz]} - r.org_perm; };
    return woop_permuted<T>(rel(v0), rel(v1), rel(v2), r.sx, r.sy, r.sz, r.tnear, r.tfar);
}

/// One ray against lanes<T> triangles stored as TrisSoA<lanes<T>> (`soa` points at its v[0][0][0]):
/// only the three axes the ray's permutation needs are loaded, already in (kx, ky, kz) order.
template <class T, bool EarlyOut = false> ARBOR_INLINE TriHit<T> ray_triangles(const WideRay<T>& r, const float* soa) {
    constexpr std::size_t n = lanes<T>;
    const auto rel = [&r, soa](std::size_t vertex) {
        const float* v = soa + vertex * 3 * n;
        return Vec3<T>{load_lanes<T>(v + std::size_t(r.kx) * n), load_lanes<T>(v + std::size_t(r.ky) * n),
                       load_lanes<T>(v + std::size_t(r.kz) * n)} -
               r.org_perm;
    };
    return woop_permuted<T, EarlyOut>(rel(0), rel(1), rel(2), r.sx, r.sy, r.sz, r.tnear, r.tfar);
}
template <class T, std::size_t N> inline TriHit<T> ray_triangles(const WideRay<T>& r, const TrisSoA<N>& tris) {
    static_assert(N == lanes<T>, "one lane per triangle");
    return ray_triangles(r, &tris.v[0][0][0]);
}

}  // namespace arbor::simd
