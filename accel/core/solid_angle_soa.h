#pragma once
/// triangle_winding (solid_angle.h) summed over the triangles of an SoA block (N triangles, float
/// corners v[k][axis][lane], as simd::TrisSoA<N> holds them), a double batch of triangles at a
/// time. The batch computes what triangle_winding computes away from a triangle's plane, in the
/// same double arithmetic with xsimd's atan2; a lane that triangle_winding would decide exactly
/// (|a.(b x c)| within 2^-20 of its permanent: near the plane, an edge or a corner) is answered
/// by triangle_winding itself, so the exact rules hold lane by lane.
#include "accel/core/solid_angle.h"
#include "simd/simd.h"

#include <cstddef>
#include <numbers>

namespace arbor::accel {

namespace detail {

/// B::size floats from p (any alignment), each made a double (exactly).
template <class B>
B widen(const float* p) {
#if XSIMD_WITH_AVX512F
    if constexpr (B::size == 8) return B(_mm512_cvtps_pd(_mm256_loadu_ps(p)));
#endif
    alignas(64) double d[B::size];
    for (std::size_t i = 0; i < B::size; ++i) d[i] = double(p[i]);
    return B::load_aligned(d);
}

}  // namespace detail

/// The sum over lanes 0 .. count - 1 of the block's triangles' winding numbers around q.
template <std::size_t N>
double soa_triangles_winding(const Vec3f& q, const float (&v)[3][3][N], std::size_t count) {
    using B = xsimd::batch<double>;
    constexpr std::size_t lanes = B::size;
    const auto corner = [&](std::size_t i, int k) { return Vec3f{v[k][0][i], v[k][1][i], v[k][2][i]}; };
    if constexpr (N % lanes != 0) {
        double sum = 0.0;
        for (std::size_t i = 0; i < count; ++i) sum += triangle_winding(q, corner(i, 0), corner(i, 1), corner(i, 2));
        return sum;
    } else {
        // Corners minus q in double, a batch of lanes at a time and only the batches in use (a
        // float difference is exact in double unless the exponents are far apart, as in
        // triangle_winding).
        const B qd[3] = {B(double(q.x)), B(double(q.y)), B(double(q.z))};
        alignas(64) double lane_ids[lanes];
        for (std::size_t i = 0; i < lanes; ++i) lane_ids[i] = double(i);
        const B ids = B::load_aligned(lane_ids);
        B angle(0.0);
        double exact_sum = 0.0;
        for (std::size_t g = 0; g < count; g += lanes) {
            const auto at = [&](int k, int a) { return detail::widen<B>(&v[k][a][g]) - qd[a]; };
            const B ax = at(0, 0), ay = at(0, 1), az = at(0, 2);
            const B bx = at(1, 0), by = at(1, 1), bz = at(1, 2);
            const B cx = at(2, 0), cy = at(2, 1), cz = at(2, 2);
            const B det = ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx);
            const B perm = xsimd::abs(ax) * (xsimd::abs(by * cz) + xsimd::abs(bz * cy)) +
                           xsimd::abs(ay) * (xsimd::abs(bz * cx) + xsimd::abs(bx * cz)) +
                           xsimd::abs(az) * (xsimd::abs(bx * cy) + xsimd::abs(by * cx));
            const auto used = ids < B(double(count - g));
            const auto plain = used && xsimd::abs(det) > B(0x1p-20) * perm;
            const B la = xsimd::sqrt(ax * ax + ay * ay + az * az), lb = xsimd::sqrt(bx * bx + by * by + bz * bz),
                    lc = xsimd::sqrt(cx * cx + cy * cy + cz * cz);
            const B den = la * lb * lc + (ax * bx + ay * by + az * bz) * lc + (ax * cx + ay * cy + az * cz) * lb +
                          (bx * cx + by * cy + bz * cz) * la;
            angle += xsimd::select(plain, xsimd::atan2(det, den), B(0.0));
            if (!xsimd::all(plain || !used)) {
                alignas(64) double exact_lanes[lanes];
                xsimd::select(used && !plain, B(1.0), B(0.0)).store_aligned(exact_lanes);
                for (std::size_t i = 0; i < lanes; ++i)
                    if (exact_lanes[i] != 0.0)
                        exact_sum += triangle_winding(q, corner(g + i, 0), corner(g + i, 1), corner(g + i, 2));
            }
        }
        return exact_sum + xsimd::hadd(angle) * (0.5 * std::numbers::inv_pi);
    }
}

}  // namespace arbor::accel
