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

namespace arbor::simd {

/// Widest float batch of this build (16 lanes with AVX-512, 8 with AVX2).
using FloatV = xsimd::batch<float>;
/// Fixed-width batches for wide nodes and packets, whatever the widest ISA.
#if XSIMD_WITH_AVX512F
using Float16 = xsimd::batch<float, xsimd::avx512bw>;
#endif
#if XSIMD_WITH_AVX2
using Float8 = xsimd::batch<float, xsimd::avx2>;
#endif
using Float4 = xsimd::batch<float, xsimd::sse4_2>;

template <class T> struct lane_traits {
    static constexpr std::size_t size = T::size;
    using mask = typename T::batch_bool_type;
};
template <> struct lane_traits<float> {
    static constexpr std::size_t size = 1;
    using mask = bool;
};
template <class T> inline constexpr std::size_t lanes = lane_traits<T>::size;
template <class T> using Mask = typename lane_traits<T>::mask;

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

/// max/min that ignore a NaN in the first operand: `rmax(a, b) = a > b ? a : b`. This is the
/// semantics of the x86 max/min instructions, so scalar and SIMD agree bit for bit. The slab test
/// folds its slab distances into a finite accumulator passed as `b`, so a NaN slab (0 * inf, a ray
/// lying in a box face plane) is ignored, which keeps the test conservative.
inline float rmax(float a, float b) { return a > b ? a : b; }
inline float rmin(float a, float b) { return a < b ? a : b; }
template <class A> inline xsimd::batch<float, A> rmax(const xsimd::batch<float, A>& a, const xsimd::batch<float, A>& b) {
    return xsimd::select(a > b, a, b);
}
template <class A> inline xsimd::batch<float, A> rmin(const xsimd::batch<float, A>& a, const xsimd::batch<float, A>& b) {
    return xsimd::select(a < b, a, b);
}

/// Lane i of a batch (or the value itself for T = float).
inline float lane(float v, std::size_t) { return v; }
template <class A> inline float lane(const xsimd::batch<float, A>& v, std::size_t i) { return v.get(i); }
inline bool lane(bool v, std::size_t) { return v; }
template <class A> inline bool lane(const xsimd::batch_bool<float, A>& m, std::size_t i) { return (to_bits(m) >> i) & 1u; }

}  // namespace arbor::simd
