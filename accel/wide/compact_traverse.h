#pragma once
/// The single-ray walk of the compact layout (compact_layout.h): the walk of wide_traverse.h
/// (walk_wide) with this layout's node test and leaf test. A node's test decodes its children's
/// quantized planes with SIMD (8-bit steps to float, compact_decode: per axis one conversion and
/// one multiply-add for the lo planes and one for the hi planes) and runs the same slab test as
/// on WideNode, masked to the node's children. A leaf is tested a block (up to N triangles) at a
/// time: the block's corner numbers and then its ORIGINAL vertices read from the block's own copy
/// through them (block_axis: a permute of one or two registers, or a gather; only the three axes
/// the ray's permutation needs, in its order), then woop_permuted, the watertight test of every
/// other path, on bit-identical inputs.
#include <immintrin.h>

#include <bit>
#include <cmath>
#include <cstdint>

#include "accel/wide/compact_layout.h"
#include "accel/wide/compact_quantize.h"
#include "accel/wide/wide_traverse.h"
#include "simd/box_kernels.h"
#include "simd/tri_kernels.h"

namespace arbor::accel {

/// lanes<T> bytes at p, each converted to float.
template <class T>
ARBOR_INLINE T load_steps(const std::uint8_t* p) {
    if constexpr (T::size == 4) {
        std::int32_t w;
        __builtin_memcpy(&w, p, 4);
        return T(_mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(w))));
    }
#if XSIMD_WITH_AVX2
    else if constexpr (T::size == 8) {
        return T(_mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)))));
    }
#endif
#if XSIMD_WITH_AVX512F
    else if constexpr (T::size == 16) {
        // (The maskz forms with every lane set: GCC 12 warns of the plain forms' undefined source.)
        return T(_mm512_maskz_cvtepi32_ps(
            0xffff, _mm512_maskz_cvtepu8_epi32(0xffff, _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)))));
    }
#endif
    else
        static_assert(T::size == 4, "no byte conversion for this width");
}

/// The decoded boxes of the children of `n`, lo planes in b[0] and hi planes in b[1] as in
/// simd::BoxesSoA (by compact_decode: each contains the child's true box).
template <std::size_t N>
inline simd::BoxesSoA<N> decode_boxes(const CompactNode<N>& n) {
    simd::BoxesSoA<N> out;
    for (int s = 0; s < 2; ++s)
        for (int k = 0; k < 3; ++k)
            for (std::size_t c = 0; c < N; ++c)
                out.b[s][k][c] = compact_decode(float(n.q[s][k][c]), n.scale[k], n.origin[k]);
    return out;
}

/// node_boxes (wide_packet.h) for a compact node: its planes decoded once for every lane of the
/// packet walk, in SIMD as node_hits decodes them (the same bits as decode_boxes).
template <std::size_t N>
ARBOR_INLINE simd::BoxesSoA<N> node_boxes(const CompactNode<N>& n) {
    using T = WideLane<N>;
    simd::BoxesSoA<N> out;
    for (int s = 0; s < 2; ++s)
        for (int k = 0; k < 3; ++k)
            simd::store_lanes(compact_decode(load_steps<T>(n.q[s][k]), T(n.scale[k]), T(n.origin[k])), out.b[s][k]);
    return out;
}

/// node_hits (wide_traverse.h) for a compact node: its planes decoded, then the slab test of
/// ray_boxes / ray_boxes_plain; only the node's children can hit.
template <bool Plain, std::size_t N>
ARBOR_INLINE std::uint32_t node_hits(const simd::WideRay<WideLane<N>>& r, const CompactNode<N>& n, WideLane<N>& t) {
    using T = WideLane<N>;
    simd::Vec3<T> near_plane, far_plane;
    for (int k = 0; k < 3; ++k) {
        // (The near and far steps picked by address, before the loads: no select after the decode.)
        const T scale(n.scale[k]), origin(n.origin[k]);
        const int hi = r.near_is_hi[k];
        near_plane[k] = compact_decode(load_steps<T>(n.q[hi][k]), scale, origin);
        far_plane[k] = compact_decode(load_steps<T>(n.q[1 - hi][k]), scale, origin);
    }
    const std::uint32_t used = (1u << n.children) - 1u;
    if constexpr (Plain)
        return simd::to_bits(
                   simd::slab_test_plain<T>(near_plane, far_plane, r.org, r.rcp_near, r.rcp_far, r.tnear, r.tbox, t)) &
               used;
    else
        return simd::to_bits(
                   simd::slab_test<T>(near_plane, far_plane, r.org, r.rcp_near, r.rcp_far, r.tnear, r.tbox, t)) &
               used;
}

template <std::size_t N>
inline const char* leaf_data(const CompactLayout<N>& layout, std::uint32_t first) {
    return reinterpret_cast<const char*>(layout.refs.data() + first);
}

/// lanes<I> bytes at p, each zero-extended to a lane of I.
template <class I>
ARBOR_INLINE I load_corners(const std::uint8_t* p) {
    if constexpr (I::size == 4) {
        std::int32_t w;
        __builtin_memcpy(&w, p, 4);
        return I(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(w)));
    }
#if XSIMD_WITH_AVX2
    else if constexpr (I::size == 8) {
        return I(_mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))));
    }
#endif
#if XSIMD_WITH_AVX512F
    else if constexpr (I::size == 16) {
        return I(_mm512_maskz_cvtepu8_epi32(0xffff, _mm_loadu_si128(reinterpret_cast<const __m128i*>(p))));
    }
#endif
    else
        static_assert(I::size == 4, "no byte conversion for this width");
}

/// Lanes<T> floats base[index[l]] for the lanes set in `lanes`, NaN in the others (never read:
/// the watertight test's padding, which never hits and never reaches its double-precision
/// fallback), by the ISA's masked gather (xsimd 8.1 emulates AVX-512 gathers lane by lane; a
/// masked gather loads only its lanes).
template <class T>
ARBOR_INLINE T gather_lanes(const float* base, const simd::IntOf<T>& index, std::uint32_t lanes) {
#if XSIMD_WITH_AVX512F
    if constexpr (T::size == 16) {
        return T(_mm512_mask_i32gather_ps(_mm512_set1_ps(NAN), __mmask16(lanes), __m512i(index), base, 4));
    } else
#endif
#if XSIMD_WITH_AVX2
    if constexpr (T::size == 8) {
        const __m256i bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
        const __m256 mask = _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(int(lanes)), bit), bit));
        return T(_mm256_mask_i32gather_ps(_mm256_set1_ps(NAN), base, __m256i(index), mask, 4));
    } else
#endif
    {
        alignas(64) std::int32_t at[T::size];
        alignas(64) float out[T::size];
        index.store_aligned(at);
        for (std::size_t l = 0; l < T::size; ++l) out[l] = (lanes >> l) & 1u ? base[at[l]] : NAN;
        return T::load_aligned(out);
    }
}

/// The block's numbers of vertex k of each of its triangles (lanes past the block's end read
/// whatever follows its corners: block_axis masks them out).
template <class T>
ARBOR_INLINE simd::IntOf<T> corner_numbers(const CompactBlock& blk, std::size_t k) {
    return load_corners<simd::IntOf<T>>(blk.corners() + k * blk.nb);
}

/// Lanes<T> floats axis[index[l]] of a block's axis of m floats, for the lanes set in `lanes`, NaN
/// in the others. 16 lanes (AVX-512): up to 32 vertices from one or two registers by a permute,
/// more by the masked gather; else the masked gather.
template <class T>
ARBOR_INLINE T block_axis(const float* axis, std::uint32_t m, const simd::IntOf<T>& index, std::uint32_t lanes) {
#if XSIMD_WITH_AVX512F
    if constexpr (T::size == 16) {
        const __m512 nan = _mm512_set1_ps(NAN);
        if (m <= 16) {
            const __m512 v = _mm512_maskz_loadu_ps(__mmask16((1u << m) - 1u), axis);
            return T(_mm512_mask_mov_ps(nan, __mmask16(lanes), _mm512_permutexvar_ps(__m512i(index), v)));
        }
        if (m <= 32) {
            const __m512 lo = _mm512_loadu_ps(axis);
            const __m512 hi = _mm512_maskz_loadu_ps(__mmask16((1u << (m - 16)) - 1u), axis + 16);
            return T(_mm512_mask_mov_ps(nan, __mmask16(lanes), _mm512_permutex2var_ps(lo, __m512i(index), hi)));
        }
    }
#endif
    return gather_lanes<T>(axis, index, lanes);
}

/// The lanes of block `blk` that hold a triangle.
template <std::size_t N>
ARBOR_INLINE std::uint32_t block_lanes(const CompactBlock& blk) {
    return blk.nb >= N ? std::uint32_t((1ull << N) - 1) : (1u << blk.nb) - 1u;
}

/// The triangles of block `blk` as a TrisSoA block (their original vertices, gathered), for the
/// packet walk; NaN in the lanes past the block's end.
template <std::size_t N>
ARBOR_INLINE void compact_block(const CompactBlock& blk, simd::TrisSoA<N>& out) {
    using T = WideLane<N>;
    const std::uint32_t lanes = block_lanes<N>(blk), m = blk.vertex_count();
    for (std::size_t k = 0; k < 3; ++k) {
        const auto at = corner_numbers<T>(blk, k);
        for (int a = 0; a < 3; ++a) simd::store_lanes(block_axis<T>(blk.axis(a), m, at, lanes), out.v[k][a]);
    }
}

/// Ray r against the triangles of block `blk`; the lanes past the block's end hold NaN vertices,
/// which never hit.
template <class T>
ARBOR_INLINE simd::TriHit<T> compact_triangles(const simd::WideRay<T>& r, const CompactBlock& blk) {
    const std::uint32_t lanes = block_lanes<T::size>(blk), m = blk.vertex_count();
    const float* ax = blk.axis(r.kx);
    const float* ay = blk.axis(r.ky);
    const float* az = blk.axis(r.kz);
    const auto rel = [&](std::size_t k) {
        const auto at = corner_numbers<T>(blk, k);
        return simd::Vec3<T>{block_axis<T>(ax, m, at, lanes), block_axis<T>(ay, m, at, lanes),
                             block_axis<T>(az, m, at, lanes)} -
               r.org_perm;
    };
    return simd::woop_permuted<T, true>(rel(0), rel(1), rel(2), r.sx, r.sy, r.sz, r.tnear, r.tfar);
}

}  // namespace arbor::accel
