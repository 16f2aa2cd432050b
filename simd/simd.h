#pragma once
/// The one xsimd include of arbor. Kernels are written once over a lane type T, which is either
/// `float` (the scalar reference) or an xsimd batch; this header supplies the few free functions
/// that xsimd 8.1 lacks for T = float (select/any/all) and the mask-to-bits conversion that it
/// lacks for batches.
#include <xsimd/xsimd.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <type_traits>

/// Forces inlining of a hot kernel into its traversal loop (GCC otherwise keeps the 16-wide
/// triangle test out of line: a call, and its results passed through memory, per leaf block).
#define ARBOR_INLINE inline __attribute__((always_inline))

namespace arbor::simd {

/// Widest float batch of this build (16 lanes with AVX-512, 8 with AVX2).
using FloatV = xsimd::batch<float>;
/// Fixed-width batches for wide nodes and packets, whatever the widest ISA. A width equal to the
/// widest one is FloatV itself, so kernels are instantiated once per width. Guard uses of Float16
/// with XSIMD_WITH_AVX512F and of Float8 with XSIMD_WITH_AVX2 (x86-64-v3 builds have no Float16).
#if XSIMD_WITH_AVX512F
static_assert(FloatV::size == 16);
using Float16 = FloatV;
#endif
#if XSIMD_WITH_AVX2
using Float8 = std::conditional_t<FloatV::size == 8, FloatV, xsimd::batch<float, xsimd::avx2>>;
#endif
using Float4 = xsimd::batch<float, xsimd::sse4_2>;

template <class T> struct lane_traits {
    static constexpr std::size_t size = T::size;
    using mask = typename T::batch_bool_type;
    using integer = xsimd::batch<std::int32_t, typename T::arch_type>;  ///< same lanes, 32-bit integers
};
template <> struct lane_traits<float> {
    static constexpr std::size_t size = 1;
    using mask = bool;
    using integer = std::int32_t;
};
template <class T> inline constexpr std::size_t lanes = lane_traits<T>::size;
template <class T> using Mask = typename lane_traits<T>::mask;
/// 32-bit integer lanes matching T (std::int32_t for T = float).
template <class T> using IntOf = typename lane_traits<T>::integer;

// Scalar shims so that `select/any/all/to_bits` read the same for T = float and for batches.
inline float select(bool m, float a, float b) { return m ? a : b; }
inline bool any(bool m) { return m; }
inline bool all(bool m) { return m; }
inline bool none(bool m) { return !m; }
inline std::uint32_t to_bits(bool m) { return m ? 1u : 0u; }
using xsimd::all;
using xsimd::any;
using xsimd::none;
using xsimd::select;

/// Bit i set when lane i of the mask is true.
template <class A> inline std::uint32_t to_bits(const xsimd::batch_bool<float, A>& m) {
#if XSIMD_WITH_AVX512F
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) return static_cast<std::uint32_t>(static_cast<__mmask16>(m));
    else
#endif
#if XSIMD_WITH_AVX
    if constexpr (std::is_base_of_v<xsimd::avx, A>) return static_cast<std::uint32_t>(_mm256_movemask_ps(static_cast<__m256>(m)));
    else
#endif
        return static_cast<std::uint32_t>(_mm_movemask_ps(static_cast<__m128>(m)));
}

/// Bit i set when lane i of the double mask is true.
template <class A> inline std::uint32_t to_bits(const xsimd::batch_bool<double, A>& m) {
#if XSIMD_WITH_AVX512F
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) return static_cast<std::uint32_t>(static_cast<__mmask8>(m));
    else
#endif
#if XSIMD_WITH_AVX
    if constexpr (std::is_base_of_v<xsimd::avx, A>) return static_cast<std::uint32_t>(_mm256_movemask_pd(static_cast<__m256d>(m)));
    else
#endif
        return static_cast<std::uint32_t>(_mm_movemask_pd(static_cast<__m128d>(m)));
}

/// max/min that ignore a NaN in the first operand: `rmax(a, b) = a > b ? a : b`. This is the
/// semantics of the x86 max/min instructions, so scalar and SIMD agree bit for bit. The slab test
/// folds its slab distances into a finite accumulator passed as `b`, so a NaN slab (0 * inf, a ray
/// lying in a box face plane) is ignored, which keeps the test conservative.
inline float rmax(float a, float b) { return a > b ? a : b; }
inline float rmin(float a, float b) { return a < b ? a : b; }
/// For batches xsimd's max/min are exactly these: MAXPS/MINPS(a, b) return b unless a > b (a < b),
/// so one instruction each instead of a compare and a blend (tested lane by lane, NaN and +-0 included).
/// (With AVX-512 the zero-masked form with a full mask: the same instruction, and no GCC 12
/// -Wmaybe-uninitialized false positive from inside the plain intrinsic.)
template <class A> inline xsimd::batch<float, A> rmax(const xsimd::batch<float, A>& a, const xsimd::batch<float, A>& b) {
#if XSIMD_WITH_AVX512F
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>)
        return _mm512_maskz_max_ps(__mmask16(0xFFFF), static_cast<__m512>(a), static_cast<__m512>(b));
    else
#endif
        return xsimd::max(a, b);
}
template <class A> inline xsimd::batch<float, A> rmin(const xsimd::batch<float, A>& a, const xsimd::batch<float, A>& b) {
#if XSIMD_WITH_AVX512F
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>)
        return _mm512_maskz_min_ps(__mmask16(0xFFFF), static_cast<__m512>(a), static_cast<__m512>(b));
    else
#endif
        return xsimd::min(a, b);
}

/// Lane i of a batch (or the value itself for T = float).
inline float lane(float v, std::size_t) { return v; }
template <class A> inline float lane(const xsimd::batch<float, A>& v, std::size_t i) { return v.get(i); }
inline bool lane(bool v, std::size_t) { return v; }
template <class A> inline bool lane(const xsimd::batch_bool<float, A>& m, std::size_t i) { return (to_bits(m) >> i) & 1u; }

/// Loads lanes<T> consecutive values from p (no alignment needed); T = float reads *p.
template <class T, class S> inline T load_lanes(const S* p) {
    if constexpr (std::is_arithmetic_v<T>) return *p;
    else return T::load_unaligned(p);
}
/// Stores lanes<T> consecutive values to p (no alignment needed).
template <class S> inline void store_lanes(S v, S* p) requires std::is_arithmetic_v<S> { *p = v; }
template <class S, class A> inline void store_lanes(const xsimd::batch<S, A>& v, S* p) { v.store_unaligned(p); }

/// Lanes whose sign bit is set, as std::signbit: true for -0, negative values and NaNs with the sign set.
inline bool signbit_mask(float x) { return std::signbit(x); }
template <class A> inline xsimd::batch_bool<float, A> signbit_mask(const xsimd::batch<float, A>& x) {
    using I = xsimd::batch<std::int32_t, A>;
    return xsimd::bool_cast(xsimd::bitwise_cast<I>(x) < I(0));
}

/// Mask whose lane i is bit i of `bits` (the inverse of to_bits).
template <class T> inline Mask<T> from_bits(std::uint32_t bits) {
    if constexpr (std::is_same_v<T, float>) {
        return (bits & 1u) != 0;
    } else {
#if XSIMD_WITH_AVX512F
        if constexpr (std::is_base_of_v<xsimd::avx512f, typename T::arch_type>)
            return Mask<T>(static_cast<__mmask16>(bits));
        else
#endif
        {
            using I = IntOf<T>;
            alignas(64) std::int32_t pow2[T::size];
            for (std::size_t i = 0; i < T::size; ++i) pow2[i] = std::int32_t(1u << i);
            return xsimd::bool_cast((I(std::int32_t(bits)) & I::load_aligned(pow2)) != I(0));
        }
    }
}
/// Mask of the first n lanes (n may exceed the lane count).
template <class T> inline Mask<T> first_lanes(std::size_t n) {
    return from_bits<T>(n >= 32 ? ~0u : (1u << n) - 1u);
}

/// select for the integer lanes that go with T, under T's mask.
inline std::int32_t iselect(bool m, std::int32_t a, std::int32_t b) { return m ? a : b; }
template <class A>
inline xsimd::batch<std::int32_t, A> iselect(const xsimd::batch_bool<float, A>& m, const xsimd::batch<std::int32_t, A>& a,
                                             const xsimd::batch<std::int32_t, A>& b) {
    return xsimd::select(xsimd::bool_cast(m), a, b);
}
#if XSIMD_WITH_AVX512F
/// Sixteen horizontal minima at once: out[i] = the smallest lane of v[i] (NaN-free batches). A
/// butterfly of 15 min and 30 shuffle instructions instead of 16 separate reductions of ~8 each.
inline void hmin16(const Float16 (&v)[16], float (&out)[16]) {
    // (The maskz forms with a full mask: the plain ones make GCC 12 warn about the undefined
    // vector inside its own header; they compile to the same instructions.)
    constexpr __mmask16 all = 0xffff;
    const auto min = [](__m512 a, __m512 b) { return _mm512_maskz_min_ps(all, a, b); };
    __m512 m[8], n[4], q[2];
    for (int i = 0; i < 8; ++i) {
        const __m512 a = v[2 * i], b = v[2 * i + 1];
        m[i] = min(_mm512_maskz_shuffle_f32x4(all, a, b, 0x44), _mm512_maskz_shuffle_f32x4(all, a, b, 0xEE));
    }
    for (int i = 0; i < 4; ++i)
        n[i] = min(_mm512_maskz_shuffle_f32x4(all, m[2 * i], m[2 * i + 1], 0x88),
                   _mm512_maskz_shuffle_f32x4(all, m[2 * i], m[2 * i + 1], 0xDD));
    for (int i = 0; i < 2; ++i)
        q[i] = min(_mm512_maskz_shuffle_ps(all, n[2 * i], n[2 * i + 1], 0x44),
                   _mm512_maskz_shuffle_ps(all, n[2 * i], n[2 * i + 1], 0xEE));
    alignas(64) float r[16];
    _mm512_store_ps(r, min(_mm512_maskz_shuffle_ps(all, q[0], q[1], 0x88), _mm512_maskz_shuffle_ps(all, q[0], q[1], 0xDD)));
    // The butterfly leaves the minimum of v[i] in lane 4 * (i % 4) + i / 4.
    for (int i = 0; i < 16; ++i) out[i] = r[4 * (i % 4) + i / 4];
}
#endif

/// Lanes where two integer batches are equal, as a mask of T.
inline bool int_equal(std::int32_t a, std::int32_t b) { return a == b; }
template <class A>
inline xsimd::batch_bool<float, A> int_equal(const xsimd::batch<std::int32_t, A>& a, const xsimd::batch<std::int32_t, A>& b) {
    return xsimd::bool_cast(a == b);
}
/// |x| per lane (clears the sign bit, as std::fabs).
inline float vabs(float x) { return std::fabs(x); }
template <class A> inline xsimd::batch<float, A> vabs(const xsimd::batch<float, A>& x) { return xsimd::abs(x); }
inline std::int32_t lane(std::int32_t v, std::size_t) { return v; }
template <class A> inline std::int32_t lane(const xsimd::batch<std::int32_t, A>& v, std::size_t i) { return v.get(i); }

/// Smallest lane of a NaN-free batch (+0 and -0 compare equal: either may come back), as a tree of
/// mins halving the width (one GCC 12 regression avoided: xsimd 8.1's avx/avx2 arch types are not
/// derived from sse2, so a test on the ISA hierarchy sent 8-lane batches to a scalar loop of seven
/// dependent mins; the tree is three).
inline float hmin(float v) { return v; }
namespace detail {
inline float hmin128(__m128 m) {
    m = _mm_min_ps(m, _mm_movehl_ps(m, m));
    m = _mm_min_ss(m, _mm_shuffle_ps(m, m, 1));
    return _mm_cvtss_f32(m);
}
}  // namespace detail
template <class A> inline float hmin(const xsimd::batch<float, A>& v) {
    constexpr std::size_t n = xsimd::batch<float, A>::size;
#if XSIMD_WITH_AVX512DQ
    // (Not _mm512_reduce_min_ps, nor the AVX512F extracts: GCC 12 warns about an uninitialized value
    // inside its own header.)
    if constexpr (n == 16) {
        const __m512 w = static_cast<__m512>(v);
        const __m256 h = _mm256_min_ps(_mm512_extractf32x8_ps(w, 0), _mm512_extractf32x8_ps(w, 1));
        return detail::hmin128(_mm_min_ps(_mm256_castps256_ps128(h), _mm256_extractf128_ps(h, 1)));
    } else
#endif
#if XSIMD_WITH_AVX
    if constexpr (n == 8) {
        const __m256 w = static_cast<__m256>(v);
        return detail::hmin128(_mm_min_ps(_mm256_castps256_ps128(w), _mm256_extractf128_ps(w, 1)));
    } else
#endif
    if constexpr (n == 4) {
        return detail::hmin128(static_cast<__m128>(v));
    } else {
        alignas(64) float x[n];
        v.store_aligned(x);
        float m = x[0];
        for (float y : x) m = rmin(y, m);
        return m;
    }
}

/// Index of the hit lane with the smallest t, the lowest index on ties; -1 when no lane hits.
/// Deterministic: the answer does not depend on the reduction order (+0 and -0 tie).
template <class T> inline int closest_lane(const Mask<T>& hit, const T& t) {
    const std::uint32_t bits = to_bits(hit);
    if (bits == 0) return -1;
    if ((bits & (bits - 1)) == 0) return std::countr_zero(bits);
    const float m = hmin(select(hit, t, T(INFINITY)));
    return std::countr_zero(to_bits(hit & (t == T(m))));
}

}  // namespace arbor::simd
