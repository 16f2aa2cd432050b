#pragma once
/// The single-ray walk of the compact layout (compact_layout.h): the walk of wide_traverse.h
/// (walk_wide) with this layout's node test and leaf test. A node's test decodes its children's
/// quantized planes with SIMD (8-bit steps to float, compact_decode: per axis one conversion and
/// one multiply-add for the lo planes and one for the hi planes) and runs the same slab test as
/// on WideNode, masked to the node's children. A leaf is tested N triangles at a time: their
/// vertex indices and then their ORIGINAL vertices gathered from the mesh's arrays (only the
/// three axes the ray's permutation needs, in its order), then woop_permuted, the watertight test
/// of every other path, on bit-identical inputs.
#include "accel/wide/compact_layout.h"
#include "accel/wide/compact_quantize.h"
#include "accel/wide/wide_traverse.h"
#include "simd/box_kernels.h"
#include "simd/tri_kernels.h"

#include <immintrin.h>

#include <bit>
#include <cstdint>

namespace arbor::accel {

/// lanes<T> bytes at p, each converted to float.
template <class T> ARBOR_INLINE T load_steps(const std::uint8_t* p) {
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
        return T(_mm512_cvtepi32_ps(_mm512_cvtepu8_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)))));
    }
#endif
    else static_assert(T::size == 4, "no byte conversion for this width");
}

/// The decoded boxes of the children of `n`, lo planes in b[0] and hi planes in b[1] as in
/// simd::BoxesSoA (by compact_decode: each contains the child's true box).
template <std::size_t N> inline simd::BoxesSoA<N> decode_boxes(const CompactNode<N>& n) {
    simd::BoxesSoA<N> out;
    for (int s = 0; s < 2; ++s)
        for (int k = 0; k < 3; ++k)
            for (std::size_t c = 0; c < N; ++c) out.b[s][k][c] = compact_decode(float(n.q[s][k][c]), n.scale[k], n.origin[k]);
    return out;
}

/// node_hits (wide_traverse.h) for a compact node: its planes decoded, then the slab test of
/// ray_boxes / ray_boxes_plain; only the node's children can hit.
template <bool Plain, std::size_t N>
ARBOR_INLINE std::uint32_t node_hits(const simd::WideRay<WideLane<N>>& r, const CompactNode<N>& n, WideLane<N>& t) {
    using T = WideLane<N>;
    simd::Vec3<T> near_plane, far_plane;
    for (int k = 0; k < 3; ++k) {
        const T scale(n.scale[k]), origin(n.origin[k]);
        const T lo = compact_decode(load_steps<T>(n.q[0][k]), scale, origin);
        const T hi = compact_decode(load_steps<T>(n.q[1][k]), scale, origin);
        near_plane[k] = r.near_is_hi[k] ? hi : lo;
        far_plane[k] = r.near_is_hi[k] ? lo : hi;
    }
    const std::uint32_t used = (1u << n.children) - 1u;
    if constexpr (Plain)
        return simd::to_bits(simd::slab_test_plain<T>(near_plane, far_plane, r.org, r.rcp_near, r.rcp_far, r.tnear, r.tfar, t)) & used;
    else return simd::to_bits(simd::slab_test<T>(near_plane, far_plane, r.org, r.rcp_near, r.rcp_far, r.tnear, r.tfar, t)) & used;
}

template <std::size_t N> inline const char* leaf_data(const CompactLayout<N>& layout, std::uint32_t first) {
    return reinterpret_cast<const char*>(layout.tris.data() + first);
}

/// Ray r against the up to N leaf triangles tris[first, first + n) of `layout` (n >= 1; the lanes
/// past n repeat the last triangle, so they hit only where it does, and never at a lower lane).
template <class T, std::size_t N>
ARBOR_INLINE simd::TriHit<T> compact_triangles(const simd::WideRay<T>& r, const CompactLayout<N>& layout, std::uint32_t first,
                                               std::uint32_t n) {
    using I = simd::IntOf<T>;
    static_assert(T::size == N);
    alignas(64) static constexpr auto iota = [] {
        std::array<std::int32_t, N> a{};
        for (std::size_t l = 0; l < N; ++l) a[l] = std::int32_t(l);
        return a;
    }();
    // Lane l reads triangle first + min(l, n - 1): four ints each (v[3], prim).
    const I lane = xsimd::min(I::load_aligned(iota.data()), I(std::int32_t(n) - 1)) * I(4);
    const auto* base = reinterpret_cast<const std::int32_t*>(layout.tris.data() + first);
    const float* ax = layout.axis[r.kx];
    const float* ay = layout.axis[r.ky];
    const float* az = layout.axis[r.kz];
    const auto rel = [&](int k) {
        const I v = I::gather(base + k, lane);
        return simd::Vec3<T>{T::gather(ax, v), T::gather(ay, v), T::gather(az, v)} - r.org_perm;
    };
    return simd::woop_permuted<T, true>(rel(0), rel(1), rel(2), r.sx, r.sy, r.sz, r.tnear, r.tfar);
}

}  // namespace arbor::accel
