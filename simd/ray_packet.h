#pragma once
/// RayPacket<T>: lanes<T> rays in SoA form, with the per-lane constants of the slab test (Ize) and
/// of the watertight triangle test (Woop), an active mask, and loading from / storing to arrays of
/// rays and hits. T = float is a one-ray packet: the scalar instantiation every kernel is checked
/// against, lane by lane.
#include "simd/ray_box.h"
#include "simd/ray.h"
#include "simd/ray_triangle.h"

#include <algorithm>
#include <cstddef>
#include <span>

namespace arbor::simd {

/// The per-lane Woop permutation as masks (kx == 0 is kx0, kx == 1 is kx1, otherwise 2; the same
/// for ky, kz) and the per-lane shear. The rule is woop_shear's: kz is the axis of the largest
/// |d| (first of equals), kx = kz+1, ky = kx+1 (mod 3), kx and ky swapped when d[kz] has its sign set.
template <class T> struct WoopLanes {
    Mask<T> kx0, kx1, ky0, ky1, kz0, kz1;
    T sx, sy, sz;
    bool uniform = true;  ///< every active lane has the permutation (kx, ky, kz) below
    int kx = 0, ky = 1, kz = 2;
};

/// v with its components put in the lane's (kx, ky, kz) order, chosen per lane with selects.
template <class T> inline Vec3<T> permute_lanes(const WoopLanes<T>& w, const Vec3<T>& v) {
    return {select(w.kx0, v.x, select(w.kx1, v.y, v.z)), select(w.ky0, v.x, select(w.ky1, v.y, v.z)),
            select(w.kz0, v.x, select(w.kz1, v.y, v.z))};
}
/// The same when every lane has the permutation (w.kx, w.ky, w.kz): plain component picks.
template <class T> inline Vec3<T> permute_uniform(const WoopLanes<T>& w, const Vec3<T>& v) {
    return {v[w.kx], v[w.ky], v[w.kz]};
}

/// Woop permutation and shear of every lane; `active` decides which lanes count for `uniform`.
template <class T> inline WoopLanes<T> woop_lanes(const Vec3<T>& dir, const Mask<T>& active) {
    WoopLanes<T> w;
    const Vec3<T> a{vabs(dir.x), vabs(dir.y), vabs(dir.z)};
    const Mask<T> gexy = a.x >= a.y, gexz = a.x >= a.z, geyz = a.y >= a.z;
    w.kz0 = gexy & gexz;
    w.kz1 = (!gexy) & geyz;
    const Mask<T> kz2 = !(w.kz0 | w.kz1);
    const Mask<T> s = signbit_mask(select(w.kz0, dir.x, select(w.kz1, dir.y, dir.z)));
    w.kx0 = (kz2 & !s) | (w.kz1 & s);
    w.kx1 = (w.kz0 & !s) | (kz2 & s);
    w.ky0 = (w.kz1 & !s) | (kz2 & s);
    w.ky1 = (kz2 & !s) | (w.kz0 & s);
    const Vec3<T> d = permute_lanes(w, dir);
    w.sx = d.x / d.z;
    w.sy = d.y / d.z;
    w.sz = T(1.0f) / d.z;
    const std::uint32_t act = to_bits(active);
    if (act != 0) {
        const auto same = [act](const Mask<T>& m) {
            const std::uint32_t b = to_bits(m) & act;
            return b == 0 || b == act;
        };
        w.uniform = same(w.kx0) && same(w.kx1) && same(w.ky0) && same(w.ky1) && same(w.kz0) && same(w.kz1);
        const std::size_t i = std::countr_zero(act);
        const auto axis = [i](const Mask<T>& m0, const Mask<T>& m1) { return lane(m0, i) ? 0 : (lane(m1, i) ? 1 : 2); };
        w.kx = axis(w.kx0, w.kx1);
        w.ky = axis(w.ky0, w.ky1);
        w.kz = axis(w.kz0, w.kz1);
    }
    return w;
}

/// lanes<T> rays. Lanes that are not traceable are inactive, with tnear = +inf and tfar = -inf so
/// that no test can accept them even without the mask; every kernel also ANDs `active`.
template <class T> struct RayPacket {
    static constexpr std::size_t size = lanes<T>;
    Vec3<T> org, dir;
    Vec3<T> rcp_near;       ///< 1/d
    Vec3<T> rcp_far;        ///< 1/d padded by 2 ulps (Ize)
    Mask<T> near_is_hi[3];  ///< sign bit of d per axis: the near plane is the box's max
    T tnear, tfar;
    T tbox;  ///< box_tfar(tfar) (ray_box.h): what the box tests cull against; a walk that lowers tfar keeps it
    Mask<T> active;
    WoopLanes<T> woop;
    /// The lanes that would be plain rays (WideRay::plain: tnear >= 0, all reciprocals finite and
    /// normal; inactive lanes may be set too), and whether every active lane is one, so that
    /// packet_box_plain may stand in for packet_box.
    Mask<T> plain_lanes;
    bool plain = false;
};

/// Packet from SoA rays; lanes outside `active` or not traceable become inactive.
///
/// Woop = false: without the triangle test's set-up (p.woop left as default-made), what the box
/// tests read, for callers that make p.woop only once some lane reaches a triangle (add_woop with
/// this packet's initial p.active): the packet is then make_packet's bit for bit. Rays that miss
/// the model, or cross only empty space near it, never need it (camera rays around a small model:
/// the three divisions and the permutation masks were ~15% of the packet path there); its
/// reciprocals by slab_rcps (three divisions fewer in most packets, the same bits).
///
/// Woop = true (the single path's set-up, wide_ray_setup, makes its rays with it): reciprocals by
/// slab_rcp per axis, woop_lanes called here. Other forms of it moved GCC 12's inlining in
/// wide_paths16.cpp (slab_rcps: push_ordered16 and refine_edges became calls, any-hit single rays
/// 0.84-0.88x; make_packet as make_packet<T, false> + add_woop: WideRaySetup::get,
/// load_packet and packet_bounds' bounded_axes became calls, packet paths 0.97x, alligator's
/// any-hit single rays down to 0.84x).
template <class T, bool Woop = true>
inline RayPacket<T> make_packet(const Vec3<T>& org, const Vec3<T>& dir, const T& tnear, const T& tfar,
                                const Mask<T>& active) {
    RayPacket<T> p;
    p.org = org;
    p.dir = dir;
    p.active = active & traceable(org, dir, tnear, tfar);
    p.tnear = select(p.active, tnear, T(INFINITY));
    p.tfar = select(p.active, tfar, T(-INFINITY));
    p.tbox = box_tfar(p.tfar);
    const T dmax = rmax(vabs(dir.x), rmax(vabs(dir.y), vabs(dir.z)));
    if constexpr (!Woop) p.rcp_near = slab_rcps(dir, dmax);
    for (int k = 0; k < 3; ++k) {
        if constexpr (Woop) p.rcp_near[k] = slab_rcp(dir[k], dmax);
        p.rcp_far[k] = slab_far(p.rcp_near[k]);
        p.near_is_hi[k] = signbit_mask(dir[k]);
    }
    if constexpr (Woop) p.woop = woop_lanes(dir, p.active);
    p.plain_lanes = is_plain(p.tnear, p.rcp_near, p.rcp_far);
    p.plain = to_bits(p.active & !p.plain_lanes) == 0;
    return p;
}

/// The triangle test's set-up of a packet made by make_packet<T, false>, whose p.active was
/// `active` then (an any-hit walk drops lanes from p.active as they finish; the set-up is the same).
template <class T> inline void add_woop(RayPacket<T>& p, const Mask<T>& active) { p.woop = woop_lanes(p.dir, active); }

/// The fields of lanes<T> rays in SoA form as loaded, before make_packet: `active` holds the lanes
/// that have a ray (traceable or not).
template <class T> struct PacketRays {
    Vec3<T> org, dir;
    T tnear, tfar;
    Mask<T> active;
};

/// The first min(rays.size(), lanes<T>) rays of an array of Ray-like records (ray.h) (members org,
/// dir, tnear, tfar) in SoA form; the remaining lanes are not active (tnear +inf, tfar -inf).
template <class T, class R> inline PacketRays<T> load_rays(std::span<const R> rays) {
    constexpr std::size_t n = lanes<T>;
    const std::size_t count = std::min(rays.size(), n);
#if XSIMD_WITH_AVX512F
    // A full packet of 32-byte records {org, tnear, dir, tfar}: two 8x8 transposes in registers
    // instead of 128 scalar stores and 8 loads that wait for them (~4% of the packet path).
    if constexpr (std::is_same_v<T, Float16> && sizeof(R) == 8 * sizeof(float) && std::is_standard_layout_v<R>) {
        if (count == n && offsetof(R, tnear) == 12 && offsetof(R, dir) == 16 && offsetof(R, tfar) == 28) {
            const float* base = reinterpret_cast<const float*>(rays.data());
            __m256 f[2][8];
            for (int h = 0; h < 2; ++h) {
                __m256 r[8], t[8], u[8];
                for (int j = 0; j < 8; ++j) r[j] = _mm256_loadu_ps(base + (8 * h + j) * 8);
                for (int j = 0; j < 4; ++j) {
                    t[2 * j] = _mm256_unpacklo_ps(r[2 * j], r[2 * j + 1]);
                    t[2 * j + 1] = _mm256_unpackhi_ps(r[2 * j], r[2 * j + 1]);
                }
                for (int j = 0; j < 2; ++j) {
                    u[4 * j] = _mm256_shuffle_ps(t[4 * j], t[4 * j + 2], 0x44);
                    u[4 * j + 1] = _mm256_shuffle_ps(t[4 * j], t[4 * j + 2], 0xEE);
                    u[4 * j + 2] = _mm256_shuffle_ps(t[4 * j + 1], t[4 * j + 3], 0x44);
                    u[4 * j + 3] = _mm256_shuffle_ps(t[4 * j + 1], t[4 * j + 3], 0xEE);
                }
                for (int k = 0; k < 4; ++k) {
                    f[h][k] = _mm256_permute2f128_ps(u[k], u[4 + k], 0x20);
                    f[h][4 + k] = _mm256_permute2f128_ps(u[k], u[4 + k], 0x31);
                }
            }
            const auto field = [&f](int k) { return T(_mm512_insertf32x8(_mm512_castps256_ps512(f[0][k]), f[1][k], 1)); };
            return {{field(0), field(1), field(2)}, {field(4), field(5), field(6)}, field(3), field(7), first_lanes<T>(n)};
        }
    }
#endif
    alignas(64) float f[8][n];
    for (std::size_t i = 0; i < n; ++i) {
        const bool have = i < count;
        f[0][i] = have ? rays[i].org.x : 0.0f;
        f[1][i] = have ? rays[i].org.y : 0.0f;
        f[2][i] = have ? rays[i].org.z : 0.0f;
        f[3][i] = have ? rays[i].dir.x : 0.0f;
        f[4][i] = have ? rays[i].dir.y : 0.0f;
        f[5][i] = have ? rays[i].dir.z : 0.0f;
        f[6][i] = have ? rays[i].tnear : INFINITY;
        f[7][i] = have ? rays[i].tfar : -INFINITY;
    }
    const auto ld = [&f](int k) { return load_lanes<T>(f[k]); };
    return {{ld(0), ld(1), ld(2)}, {ld(3), ld(4), ld(5)}, ld(6), ld(7), first_lanes<T>(count)};
}

/// Packet from the first min(rays.size(), lanes<T>) rays of an array of Ray-like records (ray.h)
/// (members org, dir, tnear, tfar); the remaining lanes are inactive (a partial packet).
template <class T, class R> inline RayPacket<T> load_packet(std::span<const R> rays) {
    const PacketRays<T> r = load_rays<T, R>(rays);
    return make_packet<T>(r.org, r.dir, r.tnear, r.tfar, r.active);
}

/// The same without the triangle test's set-up (make_packet<T, false>; add_woop makes it). A call of
/// its own, as load_packet is where GCC leaves it: inlined into the packet walk, it grew the
/// translation unit (wide_paths16.cpp) past GCC's inlining budget, which then called the single
/// walk's push_ordered16 and refine_edges instead of inlining them (any-hit single rays 0.84-0.88x).
template <class T, class R> __attribute__((noinline)) RayPacket<T> load_packet_boxes(std::span<const R> rays) {
    const PacketRays<T> r = load_rays<T, R>(rays);
    return make_packet<T, false>(r.org, r.dir, r.tnear, r.tfar, r.active);
}

/// Closest hits of a packet. A lane without a hit holds the miss record {+inf, -1, 0, 0}.
template <class T> struct PacketHit {
    T t = T(INFINITY);
    T u = T(0.0f), v = T(0.0f);
    IntOf<T> prim = IntOf<T>(-1);
};

/// The packet form of the hit record (accel/core/hit_record.h): offers hits (t, prim, u, v) in the
/// lanes `candidates`; a closest-hit record keeps those the tie rule of ray.h (closer) prefers, an
/// any-hit record every one. Returns the lanes taken (their tfar is then t).
template <bool AnyHit, class T>
inline Mask<T> offer_lanes(PacketHit<T>& best, const Mask<T>& candidates, const T& t, const IntOf<T>& prim, const T& u,
                           const T& v) {
    Mask<T> take = candidates;
    if constexpr (!AnyHit) take = take & closer<T>(t, prim, best.t, best.prim);
    best.t = select(take, t, best.t);
    best.u = select(take, u, best.u);
    best.v = select(take, v, best.v);
    best.prim = iselect(take, prim, best.prim);
    return take;
}

/// The closest-hit record of the lanes of `h` that hit (active lanes of p): the tie rule of ray.h.
/// Shrinks p.tfar in the lanes taken; returns them.
template <class T>
inline Mask<T> record_hits(PacketHit<T>& best, RayPacket<T>& p, const TriHit<T>& h, std::int32_t prim) {
    const Mask<T> take = offer_lanes<false>(best, h.hit & p.active, h.t, IntOf<T>(prim), h.u, h.v);
    p.tfar = select(take, h.t, p.tfar);
    return take;
}

#if XSIMD_WITH_AVX512F
namespace detail {
/// _mm512_shuffle_f32x4 (128-bit blocks Imm[1:0], Imm[3:2] of x, Imm[5:4], Imm[7:6] of y).
template <int Imm> inline __m512 blocks(__m512 x, __m512 y) { return _mm512_maskz_shuffle_f32x4(0xffff, x, y, Imm); }
}  // namespace detail
#endif

/// Writes the first min(hits.size(), lanes<T>) lanes to an array of Hit-like records (ray.h)
/// (members t, prim, u, v).
template <class T, class H> inline void store_hits(const PacketHit<T>& h, std::span<H> hits) {
    constexpr std::size_t n = lanes<T>;
#if XSIMD_WITH_AVX512F
    // A full packet into 16-byte records {t, prim, u, v}: a 4 x 16 transpose in registers and four
    // 64-byte stores instead of 64 scalar ones (~10% of the packet path on camera rays that miss).
    if constexpr (std::is_same_v<T, Float16> && sizeof(H) == 16 && std::is_standard_layout_v<H>) {
        if (hits.size() >= n && offsetof(H, prim) == 4 && offsetof(H, u) == 8 && offsetof(H, v) == 12) {
            // (The maskz forms with every lane set: GCC 12 warns of the plain forms' undefined source.)
            const auto unpacklo_ps = [](__m512 x, __m512 y) { return _mm512_maskz_unpacklo_ps(0xffff, x, y); };
            const auto unpackhi_ps = [](__m512 x, __m512 y) { return _mm512_maskz_unpackhi_ps(0xffff, x, y); };
            const auto unpacklo_pd = [](__m512d x, __m512d y) { return _mm512_maskz_unpacklo_pd(0xff, x, y); };
            const auto unpackhi_pd = [](__m512d x, __m512d y) { return _mm512_maskz_unpackhi_pd(0xff, x, y); };
            const __m512 t = h.t, u = h.u, v = h.v;
            const __m512 pr = _mm512_castsi512_ps(static_cast<__m512i>(h.prim));
            // Per 128-bit block k: a = t p of rays 4k, 4k+1; b = of 4k+2, 4k+3; c, d the same of u v.
            const __m512 a = unpacklo_ps(t, pr), b = unpackhi_ps(t, pr);
            const __m512 c = unpacklo_ps(u, v), d = unpackhi_ps(u, v);
            // r[j]: the records of rays 4k + j in block k.
            const __m512 r0 = _mm512_castpd_ps(unpacklo_pd(_mm512_castps_pd(a), _mm512_castps_pd(c)));
            const __m512 r1 = _mm512_castpd_ps(unpackhi_pd(_mm512_castps_pd(a), _mm512_castps_pd(c)));
            const __m512 r2 = _mm512_castpd_ps(unpacklo_pd(_mm512_castps_pd(b), _mm512_castps_pd(d)));
            const __m512 r3 = _mm512_castpd_ps(unpackhi_pd(_mm512_castps_pd(b), _mm512_castps_pd(d)));
            const __m512 x0 = detail::blocks<0x44>(r0, r1), x1 = detail::blocks<0x44>(r2, r3);  // 0 4 1 5, 2 6 3 7
            const __m512 y0 = detail::blocks<0xee>(r0, r1), y1 = detail::blocks<0xee>(r2, r3);  // 8 12 9 13, 10 14 11 15
            float* out = reinterpret_cast<float*>(hits.data());
            _mm512_storeu_ps(out, detail::blocks<0x88>(x0, x1));
            _mm512_storeu_ps(out + 16, detail::blocks<0xdd>(x0, x1));
            _mm512_storeu_ps(out + 32, detail::blocks<0x88>(y0, y1));
            _mm512_storeu_ps(out + 48, detail::blocks<0xdd>(y0, y1));
            return;
        }
    }
#endif
    alignas(64) float t[n], u[n], v[n];
    alignas(64) std::int32_t prim[n];
    store_lanes(h.t, t);
    store_lanes(h.u, u);
    store_lanes(h.v, v);
    store_lanes(h.prim, prim);
    for (std::size_t i = 0; i < std::min(hits.size(), n); ++i) {
        hits[i].t = t[i];
        hits[i].prim = static_cast<std::uint32_t>(prim[i]);
        hits[i].u = u[i];
        hits[i].v = v[i];
    }
}

}  // namespace arbor::simd
