#pragma once
/// The push of the single-ray walk: a node's hit children onto the stack in the node's order for
/// the ray's octant (wide_order.h), far to near, without a data-dependent branch. push_ordered is
/// the plain loop (every width; each entry is written and the top moves by the lane's hit bit);
/// on AVX-512, 16-wide nodes take push_ordered16: one permute into the octant's order and one
/// compress of the hit lanes per field, each stored as one vector; on AVX2, 8-wide nodes take
/// push_ordered8, the same by a table of compress permutations. All write the same entries
/// (tested on random masks and orders), and may write up to N entries past the new top.
#include "accel/util/stack_buffer.h"
#include "accel/wide/wide_layout.h"
#include "simd/simd.h"

#include <bit>
#include <cstdint>

#if XSIMD_WITH_AVX2
#include <immintrin.h>
#endif

namespace arbor::accel {

/// The stack of the single-ray walk in SoA form: per deferred child its reference (as
/// WideNode::child / count) and its box entry distance. Holds `entries` (WideLayout::stack_size()).
class WideStack {
public:
    explicit WideStack(std::size_t entries) : refs_(2 * entries), t_(entries), entries_(entries) {}
    std::uint32_t* child() { return refs_.data(); }
    std::uint32_t* count() { return refs_.data() + entries_; }
    float* t() { return t_.data(); }

private:
    StackBuffer<std::uint32_t, 1024> refs_;  ///< child, then count
    StackBuffer<float, 512> t_;
    std::size_t entries_;
};

/// Pushes the children of `n` whose bit is set in `bits` at stack position sp, in the order
/// `order` (N lanes, far to near; wide_order.h), with their entry distances d[lane]; returns the
/// new top. Writes entries sp .. sp + N - 1 whatever `bits` holds.
template <std::size_t N, class Node>
inline std::size_t push_ordered(std::uint32_t bits, const std::uint8_t* order, const Node& n, const float* d,
                                WideStack& s, std::size_t sp) {
    std::uint32_t* child = s.child();
    std::uint32_t* count = s.count();
    float* t = s.t();
    for (std::size_t j = 0; j < N; ++j) {
        const unsigned l = order[j];
        child[sp] = n.child[l];
        count[sp] = n.count[l];
        t[sp] = d[l];
        sp += (bits >> l) & 1u;
    }
    return sp;
}

#if XSIMD_WITH_AVX512F
/// push_ordered for 16-wide nodes with the distances in a 16-lane register. (Forced inline, as
/// push_hits below: GCC 12 stopped inlining them into the single walk once the packet path's
/// set-up changed in the same translation unit, wide_paths16.cpp; any-hit single rays 0.84-0.88x.)
template <class Node>
ARBOR_INLINE std::size_t push_ordered16(std::uint32_t bits, const std::uint8_t* order, const Node& n, __m512 d,
                                        WideStack& s, std::size_t sp) {
    // (The maskz forms with every lane set: GCC 12 warns of the plain forms' undefined source.)
    constexpr __mmask16 all = 0xffff;
    const __m512i perm = _mm512_maskz_cvtepu8_epi32(all, _mm_loadu_si128(reinterpret_cast<const __m128i*>(order)));
    // The hit lanes in the octant's order: the mask as a vector, permuted, and back.
    const __mmask16 hit =
        _mm512_movepi32_mask(_mm512_maskz_permutexvar_epi32(all, perm, _mm512_movm_epi32(__mmask16(bits))));
    const __m512i child = _mm512_maskz_permutexvar_epi32(all, perm, _mm512_loadu_si512(n.child));
    const __m512i count = _mm512_maskz_permutexvar_epi32(
        all, perm, _mm512_maskz_cvtepu16_epi32(all, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(n.count))));
    _mm512_storeu_si512(s.child() + sp, _mm512_maskz_compress_epi32(hit, child));
    _mm512_storeu_si512(s.count() + sp, _mm512_maskz_compress_epi32(hit, count));
    _mm512_storeu_ps(s.t() + sp, _mm512_maskz_compress_ps(hit, _mm512_maskz_permutexvar_ps(all, perm, d)));
    return sp + std::size_t(std::popcount(bits));
}
#endif

#if XSIMD_WITH_AVX2
namespace detail {
/// For each 8-bit mask, the positions of its set bits in increasing order (then zeros): AVX2 has
/// no compress instruction, so push_ordered8 permutes by this table instead.
struct Compress8 {
    std::uint8_t lanes[256][8];
    constexpr Compress8() : lanes{} {
        for (unsigned m = 0; m < 256; ++m) {
            unsigned k = 0;
            for (unsigned l = 0; l < 8; ++l)
                if ((m >> l) & 1u) lanes[m][k++] = std::uint8_t(l);
        }
    }
};
inline constexpr Compress8 compress8{};
}  // namespace detail

/// push_ordered for 8-wide nodes with the distances in an 8-lane register (AVX2): the hit bits in
/// the octant's order, then one permute per field by the composed order-and-compress index.
template <class Node>
inline std::size_t push_ordered8(std::uint32_t bits, const std::uint8_t* order, const Node& n, __m256 d, WideStack& s,
                                 std::size_t sp) {
    const __m256i perm = _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(order)));
    const __m256i lane_bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    const __m256i hit = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(int(bits)), lane_bit), lane_bit);
    const unsigned ordered = unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_permutevar8x32_epi32(hit, perm))));
    const __m256i packed = _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(detail::compress8.lanes[ordered])));
    const __m256i from = _mm256_permutevar8x32_epi32(perm, packed);  // the node lane of each pushed entry
    const __m256i child = _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(n.child)), from);
    const __m256i count = _mm256_permutevar8x32_epi32(
        _mm256_cvtepu16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(n.count))), from);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(s.child() + sp), child);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(s.count() + sp), count);
    _mm256_storeu_ps(s.t() + sp, _mm256_permutevar8x32_ps(d, from));
    return sp + std::size_t(std::popcount(bits));
}
#endif

/// The push for lane type T of width N: push_ordered16 / push_ordered8 where the build has them,
/// else push_ordered.
template <std::size_t N, class T, class Node>
ARBOR_INLINE std::size_t push_hits(std::uint32_t bits, const std::uint8_t* order, const Node& n, const T& t,
                                   WideStack& s, std::size_t sp) {
#if XSIMD_WITH_AVX512F
    if constexpr (N == 16) {
        return push_ordered16(bits, order, n, __m512(t), s, sp);
    } else
#endif
#if XSIMD_WITH_AVX2
    if constexpr (N == 8) {
        return push_ordered8(bits, order, n, __m256(t), s, sp);
    } else
#endif
    {
        alignas(64) float d[N];
        simd::store_lanes(t, d);
        return push_ordered<N>(bits, order, n, static_cast<const float*>(d), s, sp);
    }
}

}  // namespace arbor::accel
