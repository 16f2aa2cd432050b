#pragma once
/// The single-ray SIMD traversal of WideLayout<N> (TracePath::single): one slab test over all N
/// children of a node (simd::ray_boxes, Ize 2013, with the zero-direction rule of box_test.h), the
/// hit children visited nearest first through a distance-ordered stack, and the leaf work passed in
/// (typically simd::ray_triangles on the leaf's N-wide blocks). Closest hit and any hit are the
/// same loop (template<bool AnyHit>).
#include "accel/wide_layout.h"
#include "simd/lane_order.h"
#include "simd/wide_ray.h"

#include <bit>

namespace arbor::accel {

/// The lane type of an N-wide node: N floats in one register (Float16 needs an AVX-512 build).
template <std::size_t N> struct WideLaneOf;
template <> struct WideLaneOf<4> { using type = simd::Float4; };
#if XSIMD_WITH_AVX2
template <> struct WideLaneOf<8> { using type = simd::Float8; };
#endif
#if XSIMD_WITH_AVX512F
template <> struct WideLaneOf<16> { using type = simd::Float16; };
#endif
template <std::size_t N> using WideLane = typename WideLaneOf<N>::type;

/// Whether this build has the lane type of width N.
template <std::size_t N> constexpr bool wide_width_available() {
    if constexpr (N == 4) return true;
    else if constexpr (N == 8) return XSIMD_WITH_AVX2 != 0;
    else if constexpr (N == 16) return XSIMD_WITH_AVX512F != 0;
    else return false;
}

/// A deferred child: reference as in WideNode::child/count, and its box entry distance.
struct WideStackEntry {
    std::uint32_t child, count;
    float t;
};

/// Walks the subtree (child, count) of `layout` (the root is (0, 0)) for ray `r`. `tfar` is the
/// scalar copy of the ray's far distance: `leaf(first_block, count)` tests a leaf, and when it finds
/// a hit it lowers both `tfar` and r.tfar and returns true; with AnyHit that ends the walk. A popped
/// entry farther than tfar is skipped. `stack` holds layout.stack_size() entries. The caller checks
/// that the ray is traceable (r.traceable) and the layout not empty.
template <bool AnyHit, bool Plain = false, std::size_t N, class LeafFn>
inline void traverse_wide(const WideLayout<N>& layout, simd::WideRay<WideLane<N>>& r, const float& tfar,
                          WideStackEntry* stack, std::uint32_t child, std::uint32_t count, LeafFn&& leaf) {
    using T = WideLane<N>;
    const WideNode<N>* nodes = layout.nodes.data();
    const WideBlock<N>* blocks = layout.blocks.data();
    std::size_t sp = 0;
    for (;;) {
        if (count == 0) {
            const WideNode<N>& n = nodes[child];
            T t;
            std::uint32_t bits;
            if constexpr (Plain) bits = simd::to_bits(simd::ray_boxes_plain<T>(r, &n.boxes.b[0][0][0], t));
            else bits = simd::to_bits(simd::ray_boxes<T>(r, &n.boxes.b[0][0][0], t));
            if (bits != 0) {
                if ((bits & (bits - 1)) == 0) {  // one child hit: no ordering, no push
                    const int i = std::countr_zero(bits);
                    child = n.child[i], count = n.count[i];
                    continue;
                }
                // Deferred children are visited later: start loading them now.
                for (std::uint32_t m = bits; m != 0; m &= m - 1) {
                    const int c = std::countr_zero(m);
                    const char* p = n.count[c] ? reinterpret_cast<const char*>(blocks + n.child[c])
                                               : reinterpret_cast<const char*>(nodes + n.child[c]);
                    // Every line of a node (boxes, child and count), the vertex lines of a
                    // block's first 8 (of 9) arrays: measured over every other line, +5% on random rays.
                    for (std::size_t q = 0; q < sizeof(WideNode<N>) / 64; ++q) _mm_prefetch(p + 64 * q, _MM_HINT_T0);
                }
                alignas(64) float d[N];
                t.store_aligned(d);
                const int a = std::countr_zero(bits);
                bits &= bits - 1;
                if ((bits & (bits - 1)) == 0) {  // two: one compare
                    const int b = std::countr_zero(bits);
                    const int near = d[b] < d[a] ? b : a, far = near == a ? b : a;
                    stack[sp++] = {n.child[far], n.count[far], d[far]};
                    child = n.child[near], count = n.count[near];
                    continue;
                }
                std::uint8_t order[N];
                const int k = simd::order_hits(bits | (1u << a), static_cast<const float*>(d), order);
                for (int j = k - 1; j > 0; --j) stack[sp++] = {n.child[order[j]], n.count[order[j]], d[order[j]]};
                child = n.child[order[0]], count = n.count[order[0]];
                continue;
            }
        } else if (leaf(child, count) && AnyHit) {
            return;
        }
        // Pop the nearest deferred child that can still hold a hit.
        for (;;) {
            if (sp == 0) return;
            const WideStackEntry& e = stack[--sp];
            if (e.t <= tfar) {
                child = e.child, count = e.count;
                break;
            }
        }
    }
}

}  // namespace arbor::accel
