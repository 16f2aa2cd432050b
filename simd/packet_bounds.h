#pragma once
/// Interval bounds of a ray packet, to cull the children of a wide node for the whole packet with
/// one SIMD test (interval arithmetic over the packet's origins and reciprocal directions: see
/// Wald, Boulos, Shirley, "Ray Tracing Deformable Scenes using Dynamic Bounding Volume
/// Hierarchies", TOG 2007, and Reshetov, Soupikov, Hurley, "Multi-Level Ray Tracing Algorithm",
/// SIGGRAPH 2005).
///
/// Exactly conservative, not just approximately: the bounds are computed by the same rounded
/// operations as the per-lane slab test of ray_box.h, ((plane - origin) * reciprocal), from the
/// extreme inputs, and rounding is monotone, so a bound is never on the wrong side of a lane's
/// computed distance. Axes on which the lanes' directions differ in sign, or on which a lane's
/// reciprocal is NaN (ray_box.h, slab_rcp), are left out (they constrain nothing), and a lane's NaN slab distance (origin in the plane, zero direction) is
/// matched by an infinite bound. Hence: if any lane's slab test hits a box, bounds_boxes says the
/// box may be hit (tested lane by lane in tests/test_packet_bounds.cpp).
#include "simd/ray_packet.h"

namespace arbor::simd {

/// Bounds over a set of lanes of a packet. Axis k takes part when bit k of `axes` is set: all
/// lanes share the sign bit of d[k]. On an axis whose sign bit is set everything is negated
/// (origins, planes and reciprocals), which is exact and turns the axis into a positive one.
struct PacketBounds {
    std::uint32_t axes = 0;
    int neg[3] = {};
    float o_lo[3] = {}, o_hi[3] = {};    ///< origin (negated on negative axes): min and max
    float rn_lo[3] = {}, rn_hi[3] = {};  ///< 1/d (negated: >= 0): min and max
    float rf_lo[3] = {}, rf_hi[3] = {};  ///< padded 1/d (negated: >= 0): min and max
    float tnear_lo = INFINITY;           ///< smallest tnear
};

namespace detail {
inline bool is_nan(float x) { return std::isnan(x); }
template <class A> inline xsimd::batch_bool<float, A> is_nan(const xsimd::batch<float, A>& x) { return xsimd::isnan(x); }
template <class P> inline float masked_min(const P& x, const Mask<P>& m) { return hmin(select(m, x, P(INFINITY))); }
template <class P> inline float masked_max(const P& x, const Mask<P>& m) { return -hmin(select(m, -x, P(INFINITY))); }

/// The axes the bounds of the lanes `bits` of `p` may use: bit k when all those lanes share the
/// sign bit of d[k] (`neg` gets it) and none has a NaN reciprocal on k (slab_rcp: that axis never
/// culls for such a lane, so neither may the bounds). Mixed signs leave the axis out too.
template <class P> inline std::uint32_t bounded_axes(const RayPacket<P>& p, std::uint32_t bits, std::uint32_t& neg) {
    std::uint32_t axes = 0;
    neg = 0;
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t s = to_bits(p.near_is_hi[k]) & bits;
        if (s != 0) neg |= 1u << k;
        if (s != 0 && s != bits) continue;
        // (!(x == x), not x != x: xsimd 8's != on floats is the ordered compare, false for NaN.)
        if (to_bits(!(p.rcp_near[k] == p.rcp_near[k])) & bits) continue;
        axes |= 1u << k;
    }
    return axes;
}
}  // namespace detail

/// Bounds of the lanes `lanes` of `p` (which must be active, hence finite). No lanes: no box passes.
/// The plain form, one reduction per bound (any lane type).
template <class P> ARBOR_INLINE PacketBounds packet_bounds_plain(const RayPacket<P>& p, const Mask<P>& lanes) {
    PacketBounds b;
    const std::uint32_t bits = to_bits(lanes);
    if (bits == 0) return b;
    b.tnear_lo = detail::masked_min(p.tnear, lanes);
    std::uint32_t neg = 0;
    const std::uint32_t axes = detail::bounded_axes(p, bits, neg);
    for (int k = 0; k < 3; ++k) {
        if (!((axes >> k) & 1u)) continue;
        b.axes |= 1u << k;
        b.neg[k] = (neg >> k) & 1u;
        const P sign(b.neg[k] ? -1.0f : 1.0f);  // multiplying by -1 is an exact negation
        const P o = p.org[k] * sign, rn = p.rcp_near[k] * sign, rf = p.rcp_far[k] * sign;
        // A lane whose reciprocal is NaN (slab_rcp: a direction component too small to be sure of)
        // never culls on this axis: neither may the bounds.
        if ((to_bits(detail::is_nan(rn) | detail::is_nan(rf)) & bits) != 0) {
            b.axes &= ~(1u << k);
            continue;
        }
        b.o_lo[k] = detail::masked_min(o, lanes), b.o_hi[k] = detail::masked_max(o, lanes);
        b.rn_lo[k] = detail::masked_min(rn, lanes), b.rn_hi[k] = detail::masked_max(rn, lanes);
        b.rf_lo[k] = detail::masked_min(rf, lanes), b.rf_hi[k] = detail::masked_max(rf, lanes);
    }
    return b;
}

/// The same; for 16-lane packets with the reductions batched (bit-identical to packet_bounds_plain).
/// (Inline, so that the result is built in the caller's object: returned as a copy, its fields'
/// scalar stores were read back by two vector loads, a store-forwarding stall; likewise the six
/// reciprocal bounds are put in a register directly, not stored one by one and loaded back as a
/// vector. Together ~40% of this function's time on packets of shadow rays, perf annotate.)
template <class P> ARBOR_INLINE PacketBounds packet_bounds(const RayPacket<P>& p, const Mask<P>& lanes) {
#if XSIMD_WITH_AVX512F
    if constexpr (std::is_same_v<P, Float16>) {
        PacketBounds b;
        const std::uint32_t bits = to_bits(lanes);
        if (bits == 0) return b;
        // Incoherent packets leave axes out (mixed signs); with one axis or none left, the plain
        // form's few reductions are cheaper.
        std::uint32_t neg = 0;
        const std::uint32_t axes = detail::bounded_axes(p, bits, neg);
        if (std::popcount(axes) < 2) return packet_bounds_plain(p, lanes);
        // The same bounds with the 13 reductions done at once (hmin16), and the padded reciprocals'
        // bounds taken from the unpadded ones: on an axis that takes part every lane's reciprocal
        // has the axis' sign, so after the negation all are > 0, and slab_far is monotone on the
        // values slab_rcp gives (ray_box.h: its denormals are at least 3 ulps below FLT_MIN) and
        // commutes with the negation: min and max of the padded ones are the padded min and max.
        // The same bounds as packet_bounds_plain (tested).
        const P inf(INFINITY);
        P v[16];
        for (int k = 0; k < 3; ++k) {
            const P sign((neg >> k) & 1u ? -1.0f : 1.0f);
            const P o = p.org[k] * sign, rn = p.rcp_near[k] * sign;
            v[4 * k] = select(lanes, o, inf);
            v[4 * k + 1] = select(lanes, -o, inf);
            v[4 * k + 2] = select(lanes, rn, inf);
            v[4 * k + 3] = select(lanes, -rn, inf);
        }
        v[12] = select(lanes, p.tnear, inf);
        v[13] = v[14] = v[15] = inf;
        alignas(64) float m[16];
        hmin16(v, m);
        b.tnear_lo = m[12];
        b.axes = axes;
        for (int k = 0; k < 3; ++k) {
            if (!((axes >> k) & 1u)) continue;
            b.neg[k] = (neg >> k) & 1u;
            b.o_lo[k] = m[4 * k], b.o_hi[k] = -m[4 * k + 1];
            b.rn_lo[k] = m[4 * k + 2], b.rn_hi[k] = -m[4 * k + 3];
        }
        // The six paddings in one batch slab_far (bit-identical to the scalar one, no nextafter calls).
        alignas(64) float rf[16];
        slab_far(Float16(_mm512_setr_ps(m[2], m[6], m[10], 0.0f, -m[3], -m[7], -m[11], 0.0f, 0.0f, 0.0f, 0.0f, 0.0f,
                                        0.0f, 0.0f, 0.0f, 0.0f)))
            .store_aligned(rf);
        for (int k = 0; k < 3; ++k)
            if ((axes >> k) & 1u) b.rf_lo[k] = rf[k], b.rf_hi[k] = rf[4 + k];
        return b;
    } else
#endif
    {
        return packet_bounds_plain(p, lanes);
    }
}

/// Which of lanes<T> boxes [lo, hi] some lane of the bounded set may hit, for lanes whose tfar is
/// at most `tfar_hi`. A conservative superset: it never drops a box that a lane's slab test
/// (ray_box.h) hits.
template <class T>
inline Mask<T> bounds_boxes(const PacketBounds& b, float tfar_hi, const Vec3<T>& lo, const Vec3<T>& hi) {
    const T zero(0.0f), inf(INFINITY);
    T entry(b.tnear_lo), exit(tfar_hi);
    for (int k = 0; k < 3; ++k) {
        if (!((b.axes >> k) & 1u)) continue;
        const T sign(b.neg[k] ? -1.0f : 1.0f);
        const T near_plane = (b.neg[k] ? hi[k] : lo[k]) * sign, far_plane = (b.neg[k] ? lo[k] : hi[k]) * sign;
        // Entry: the smallest (near - o) * rn over the lanes, from the smallest near - o.
        const T a_lo = near_plane - T(b.o_hi[k]), a_hi = near_plane - T(b.o_lo[k]);
        T e = select(a_lo >= zero, a_lo * T(b.rn_lo[k]), a_lo * T(b.rn_hi[k]));
        if (b.rn_hi[k] == INFINITY) e = select((a_lo <= zero) & (a_hi >= zero), -inf, e);  // 0 * inf in a lane
        // Exit: the largest (far - o) * rf, from the largest far - o.
        const T f_hi = far_plane - T(b.o_lo[k]), f_lo = far_plane - T(b.o_hi[k]);
        T x = select(f_hi >= zero, f_hi * T(b.rf_hi[k]), f_hi * T(b.rf_lo[k]));
        if (b.rf_hi[k] == INFINITY) x = select((f_lo <= zero) & (f_hi >= zero), inf, x);
        entry = rmax(e, entry);  // a NaN bound (overflow, NaN input) is ignored, as in slab_test
        exit = rmin(x, exit);
    }
    return slab_accept(entry, exit);  // slab_test's rule, monotone in the exit
}

/// The same for lanes<T> boxes stored as BoxesSoA<lanes<T>> at `soa`.
template <class T> inline Mask<T> bounds_boxes(const PacketBounds& b, float tfar_hi, const float* soa) {
    constexpr std::size_t n = lanes<T>;
    Vec3<T> lo, hi;
    for (std::size_t k = 0; k < 3; ++k) {
        lo[int(k)] = load_lanes<T>(soa + k * n);
        hi[int(k)] = load_lanes<T>(soa + (3 + k) * n);
    }
    return bounds_boxes<T>(b, tfar_hi, lo, hi);
}

/// Which of the lanes<T> triangles of a TrisSoA block (vertices v[vertex][axis][lane] at `soa`)
/// some lane of the bounded set may hit: bounds_boxes on the triangles' bounding boxes. A NaN
/// (padding) triangle is never dropped here; callers mask the used lanes.
template <class T> inline Mask<T> bounds_triangles(const PacketBounds& b, float tfar_hi, const float* soa) {
    constexpr std::size_t n = lanes<T>;
    Vec3<T> lo, hi;
    for (std::size_t k = 0; k < 3; ++k) {
        const T a = load_lanes<T>(soa + k * n), c = load_lanes<T>(soa + (3 + k) * n), d = load_lanes<T>(soa + (6 + k) * n);
        lo[int(k)] = rmin(a, rmin(c, d));
        hi[int(k)] = rmax(a, rmax(c, d));
    }
    return bounds_boxes<T>(b, tfar_hi, lo, hi);
}

}  // namespace arbor::simd
