#pragma once
/// WideRaySetup<P>: the per-ray constants of WideRay for lanes<P> rays at once. The single-ray
/// path walks one ray at a time, but its set-up (finiteness rule, reciprocals and their padding,
/// Woop permutation and shear: divisions and data-dependent choices) vectorizes across rays: the
/// packet code of ray_packet.h works it out for a whole group, and each ray then only broadcasts
/// its lane. Bit for bit the WideRay that wide_ray() makes (tested field by field, stiff rays
/// included); in one-process A/B on the benchmark ray files it made the single path 1.03-1.17x
/// faster (the per-ray wide_ray() was ~10% of its time, ~190 instructions per ray).
#include "simd/ray_packet.h"
#include "simd/wide_ray.h"

#include <span>

namespace arbor::simd {

/// The widest lane type of the build, for the set-up of a group of rays.
#if XSIMD_WITH_AVX512F
using SetupLane = Float16;
#elif XSIMD_WITH_AVX2
using SetupLane = Float8;
#else
using SetupLane = Float4;
#endif

template <class P> struct WideRaySetup {
    static constexpr std::size_t size = lanes<P>;
    enum Field {
        org_x,
        org_y,
        org_z,
        perm_x,
        perm_y,
        perm_z,
        rn_x,
        rn_y,
        rn_z,
        rf_x,
        rf_y,
        rf_z,
        tnear,
        tfar,
        tbox,
        sx,
        sy,
        sz,
        fields
    };
    alignas(64) float f[fields][size];
    alignas(64) std::int32_t axis[3][size];  ///< kx, ky, kz per lane
    std::uint32_t traceable = 0, plain = 0;  ///< per lane, as bits
    std::uint32_t near_is_hi[3] = {};

    /// The WideRay of lane i (meaningful only where traceable; otherwise just traceable = false).
    template <class T> void get(std::size_t i, WideRay<T>& r) const {
        const auto v = [this, i](Field k) { return T(f[k][i]); };
        r.org = {v(org_x), v(org_y), v(org_z)};
        r.org_perm = {v(perm_x), v(perm_y), v(perm_z)};
        r.rcp_near = {v(rn_x), v(rn_y), v(rn_z)};
        r.rcp_far = {v(rf_x), v(rf_y), v(rf_z)};
        r.tnear = v(tnear);
        r.tfar = v(tfar);
        r.tbox = v(tbox);
        r.sx = v(sx);
        r.sy = v(sy);
        r.sz = v(sz);
        for (int k = 0; k < 3; ++k) r.near_is_hi[k] = int((near_is_hi[k] >> i) & 1u);
        r.kx = axis[0][i];
        r.ky = axis[1][i];
        r.kz = axis[2][i];
        r.traceable = ((traceable >> i) & 1u) != 0;
        r.plain = ((plain >> i) & 1u) != 0;
    }
};

/// The set-up of the active lanes of packet p, as wide_ray() gives it for each lane's ray with the
/// lane's current tfar (inactive lanes: not traceable).
template <class P> inline void wide_ray_setup(const RayPacket<P>& p, WideRaySetup<P>& s) {
    using S = WideRaySetup<P>;
    for (int k = 0; k < 3; ++k) {
        store_lanes(p.org[k], s.f[S::org_x + k]);
        store_lanes(p.rcp_near[k], s.f[S::rn_x + k]);
        store_lanes(p.rcp_far[k], s.f[S::rf_x + k]);
        s.near_is_hi[k] = to_bits(p.near_is_hi[k]);
    }
    const Vec3<P> perm = permute_lanes(p.woop, p.org);
    for (int k = 0; k < 3; ++k) store_lanes(perm[k], s.f[S::perm_x + k]);
    store_lanes(p.tnear, s.f[S::tnear]);
    store_lanes(p.tfar, s.f[S::tfar]);
    store_lanes(p.tbox, s.f[S::tbox]);
    store_lanes(p.woop.sx, s.f[S::sx]);
    store_lanes(p.woop.sy, s.f[S::sy]);
    store_lanes(p.woop.sz, s.f[S::sz]);
    // The axis numbers from the permutation masks (0 where m0, else 1 where m1, else 2), by blends
    // or arithmetic on the bits: as conditions GCC 12 made them 48 branches per group, mispredicted
    // on rays of mixed directions (random rays 1.04-1.08x without them).
    const std::uint32_t masks[3][2] = {{to_bits(p.woop.kx0), to_bits(p.woop.kx1)},
                                       {to_bits(p.woop.ky0), to_bits(p.woop.ky1)},
                                       {to_bits(p.woop.kz0), to_bits(p.woop.kz1)}};
    for (int k = 0; k < 3; ++k) {
#if XSIMD_WITH_AVX512F
        if constexpr (S::size == 16) {  // two blends by the masks
            const __m512i a =
                _mm512_mask_blend_epi32(__mmask16(masks[k][1]), _mm512_set1_epi32(2), _mm512_set1_epi32(1));
            _mm512_store_si512(s.axis[k], _mm512_mask_blend_epi32(__mmask16(masks[k][0]), a, _mm512_setzero_si512()));
            continue;
        }
#endif
        for (std::size_t i = 0; i < S::size; ++i) {
            const std::int32_t m0 = std::int32_t((masks[k][0] >> i) & 1u), m1 = std::int32_t((masks[k][1] >> i) & 1u);
            s.axis[k][i] = (2 - m1) * (1 - m0);
        }
    }
    s.traceable = to_bits(p.active);
    s.plain = to_bits(p.active & p.plain_lanes);
}

/// The set-up of rays[0, min(size, lanes<P>)) (the lanes beyond are not traceable).
template <class P, class R> inline void wide_ray_setup(std::span<const R> rays, WideRaySetup<P>& s) {
    wide_ray_setup(load_packet<P, R>(rays), s);
}

}  // namespace arbor::simd
