#pragma once
/// BinBox: what one bin of the binned SAH builder (bvh_build_sah.cpp) keeps about its primitives,
/// their box and their centroid box, as 16 floats that are all minima: lo, -hi, centroid lo,
/// -centroid hi (x, y, z and an unused lane each). Adding a primitive is one 16-lane minimum (one
/// AVX-512 instruction, two AVX or four SSE), where a box and a centroid box kept as lo/hi take a
/// min and a max each. With the centroid box kept per bin, the boxes and centroid boxes of both
/// sides of a split are unions of bins, so the partition pass only moves primitives.
///
/// Zeros are kept as +0 (x + 0 and 0 - x: -0 becomes +0, every other value is exact), so a minimum
/// does not depend on the order in which equal values meet (min(+0, -0) returns its second
/// operand): bins merged in any order, by any number of threads, hold the same bits.
#include "accel/core/geometry.h"

#include <immintrin.h>

#include <cstdint>
#include <limits>

namespace arbor::accel::detail {

/// The 16 lanes in registers, with the two operations the bins need.
struct BinLanes {
#if defined(__AVX512F__)
    __m512 v;
    static BinLanes load(const float* p) { return {_mm512_loadu_ps(p)}; }
    void store(float* p) const { _mm512_storeu_ps(p, v); }
    // (Zero-masked with every lane kept: the plain intrinsic's undefined pass-through register makes
    // GCC 12 warn -Wmaybe-uninitialized; the same instruction.)
    static BinLanes min(const BinLanes& a, const BinLanes& b) { return {_mm512_maskz_min_ps(__mmask16(0xFFFF), a.v, b.v)}; }
    static BinLanes of(__m128 a, __m128 b, __m128 c, __m128 d) {
        const __m512 ab = _mm512_insertf32x4(_mm512_zextps128_ps512(a), b, 1);
        return {_mm512_insertf32x4(_mm512_insertf32x4(ab, c, 2), d, 3)};
    }
#elif defined(__AVX__)
    __m256 v[2];
    static BinLanes load(const float* p) { return {{_mm256_loadu_ps(p), _mm256_loadu_ps(p + 8)}}; }
    void store(float* p) const { _mm256_storeu_ps(p, v[0]), _mm256_storeu_ps(p + 8, v[1]); }
    static BinLanes min(const BinLanes& a, const BinLanes& b) {
        return {{_mm256_min_ps(a.v[0], b.v[0]), _mm256_min_ps(a.v[1], b.v[1])}};
    }
    static BinLanes of(__m128 a, __m128 b, __m128 c, __m128 d) {
        return {{_mm256_set_m128(b, a), _mm256_set_m128(d, c)}};
    }
#else
    __m128 v[4];
    static BinLanes load(const float* p) { return {{_mm_loadu_ps(p), _mm_loadu_ps(p + 4), _mm_loadu_ps(p + 8), _mm_loadu_ps(p + 12)}}; }
    void store(float* p) const { _mm_storeu_ps(p, v[0]), _mm_storeu_ps(p + 4, v[1]), _mm_storeu_ps(p + 8, v[2]), _mm_storeu_ps(p + 12, v[3]); }
    static BinLanes min(const BinLanes& a, const BinLanes& b) {
        return {{_mm_min_ps(a.v[0], b.v[0]), _mm_min_ps(a.v[1], b.v[1]), _mm_min_ps(a.v[2], b.v[2]), _mm_min_ps(a.v[3], b.v[3])}};
    }
    static BinLanes of(__m128 a, __m128 b, __m128 c, __m128 d) { return {{a, b, c, d}}; }
#endif
    /// A primitive's record from its box (lane 3 of both: 0) and centroid.
    static BinLanes prim(__m128 lo, __m128 hi, __m128 c) {
        const __m128 zero = _mm_setzero_ps();
        return of(_mm_add_ps(lo, zero), _mm_sub_ps(zero, hi), _mm_add_ps(c, zero), _mm_sub_ps(zero, c));
    }
};

/// One bin's record (see above), on a cache line of its own; empty: every lane +inf.
struct alignas(64) BinBox {
    float v[16];

    void clear() {
        for (float& x : v) x = std::numeric_limits<float>::infinity();
    }
    void grow(const BinLanes& p) { BinLanes::min(BinLanes::load(v), p).store(v); }
    void grow(const BinBox& o) { grow(BinLanes::load(o.v)); }
    /// Box and centroid box (0 - x undoes the negation: +0 for a zero, exact otherwise).
    Bounds box() const { return {{v[0], v[1], v[2]}, {0.0f - v[4], 0.0f - v[5], 0.0f - v[6]}}; }
    Bounds centroid_box() const { return {{v[8], v[9], v[10]}, {0.0f - v[12], 0.0f - v[13], 0.0f - v[14]}}; }
};

}  // namespace arbor::accel::detail
