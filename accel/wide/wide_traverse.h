#pragma once
/// The single-ray SIMD traversal of WideLayout<N> (TracePath::single): one slab test over all N
/// children of a node (simd::ray_boxes, Ize 2013, with the zero-direction rule of ray_box.h), the
/// hit children pushed in the node's order for the ray's octant (wide_order.h) and visited from
/// the top of the stack, and the leaf work passed in
/// (typically simd::ray_triangles on the leaf's N-wide blocks). Closest hit and any hit are the
/// same loop (template<bool AnyHit>).
#include "accel/wide/wide_layout.h"
#include "accel/wide/wide_order.h"
#include "accel/wide/wide_push.h"
#include "simd/wide_ray.h"

#include <bit>
#include <type_traits>

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

/// Ray r's test of the N children of `n` at once: the hit bits, the entry distances in t.
template <bool Plain, std::size_t N>
ARBOR_INLINE std::uint32_t node_hits(const simd::WideRay<WideLane<N>>& r, const WideNode<N>& n, WideLane<N>& t) {
    if constexpr (Plain)
        return simd::to_bits(simd::ray_boxes_plain<WideLane<N>>(r, &n.boxes.b[0][0][0], t));
    else
        return simd::to_bits(simd::ray_boxes<WideLane<N>>(r, &n.boxes.b[0][0][0], t));
}

/// Where the leaf starting at block `first` begins (the walk prefetches it).
template <std::size_t N>
inline const char* leaf_data(const WideLayout<N>& layout, std::uint32_t first) {
    return reinterpret_cast<const char*>(layout.blocks.data() + first);
}

namespace detail {
/// The walk of traverse_wide and traverse_wide_root: from (child, count); Root: with the root's
/// children `root_rest` (entry distances `root_t`) deferred first, pushed as a node's hit
/// children are (the root test done by the caller, wide_root.h), and when (child, count) is a
/// node, its test's outcome given too (`first_bits`, distances at `first_t`: test_root's).
/// `Layout` is WideLayout<N> or CompactLayout<N> (compact_traverse.h): the walk reads its
/// `nodes` and `orders`, tests a node by node_hits and prefetches a leaf at leaf_data, both
/// overloaded per node type.
/// Count: the counted walk (WideBvhAccel::trace_counted), which adds one to `*node_tests` per node
/// whose N boxes it tests; its own instantiation, so the timed walks carry no counter code.
template <bool AnyHit, bool Plain, bool Root, bool Count = false, class Layout, class LeafFn,
          std::size_t N = Layout::width>
ARBOR_INLINE void walk_wide(const Layout& layout, simd::WideRay<WideLane<N>>& r, const float& tfar, WideStack& stack,
                            std::uint32_t child, std::uint32_t count, std::uint32_t root_rest,
                            const WideLane<N>& root_t, std::uint32_t first_bits, const float* first_t, LeafFn&& leaf,
                            std::uint64_t* node_tests = nullptr) {
    using T = WideLane<N>;
    using Node = std::remove_cvref_t<decltype(layout.nodes[0])>;
    const Node* nodes = layout.nodes.data();
    const std::uint8_t* orders = layout.orders.data() + std::size_t(ray_octant(r.near_is_hi)) * N;
    const std::uint32_t* stack_child = stack.child();
    const std::uint32_t* stack_count = stack.count();
    const float* stack_t = stack.t();
    std::size_t sp = 0;
    // The boxes are culled against box_tfar(tfar) (ray_box.h: room for a triangle's t rounded below
    // its box's entry), here and in r.tbox for the node tests (the caller's: wide_ray and
    // WideRaySetup::get set it); worked out again after a leaf that found a hit, when tfar drops.
    float tbox = simd::box_tfar(tfar);
    // Pops the nearest deferred child that can still hold a hit; false when there is none.
    const auto pop = [&]() {
        for (;;) {
            if (sp == 0) return false;
            --sp;
            // slab_test's rule (room for a negative tfar, reachable when tnear < 0); plain rays
            // have tfar >= 0, where it is the plain comparison.
            if (Plain ? stack_t[sp] <= tbox : bool(simd::slab_accept(stack_t[sp], tbox))) {
                child = stack_child[sp], count = stack_count[sp];
                return true;
            }
        }
    };
    if constexpr (Root) {
        // The deferred children of the root (no prefetch: every ray tests the root, so its
        // children are in cache); the walk goes on at (child, count) meanwhile.
        sp = push_hits<N>(root_rest, orders, nodes[0], root_t, stack, 0);
    }
    bool first = Root;  // Root: the first node's test is done (first_bits, first_t)
    for (;;) {
        if (count == 0) {
            const Node& n = nodes[child];
            T t;
            std::uint32_t bits;
            if (first) {
                bits = first_bits;
                t = simd::load_lanes<T>(first_t);
            } else
                bits = node_hits<Plain>(r, n, t);
            if constexpr (Count) *node_tests += first ? 0u : 1u;
            first = false;
            if (bits != 0) {
                if ((bits & (bits - 1)) == 0) {  // one child hit: no push (measured 1.0-1.07x on shadow rays)
                    const int i = std::countr_zero(bits);
                    child = n.child[i], count = n.count[i];
                    continue;
                }
                sp = push_hits<N>(bits, orders + std::size_t(child) * 8 * N, n, t, stack, sp);
                // Deferred children are visited later: start loading them now (every line of a node,
                // the vertex lines of a block's first 8 of 9 arrays; 1.0-1.1x on random rays).
                for (std::uint32_t m = bits; m != 0; m &= m - 1) {
                    const int c = std::countr_zero(m);
                    const char* p =
                        n.count[c] ? leaf_data(layout, n.child[c]) : reinterpret_cast<const char*>(nodes + n.child[c]);
                    for (std::size_t q = 0; q < sizeof(Node) / 64; ++q) _mm_prefetch(p + 64 * q, _MM_HINT_T0);
                }
            }
        } else {
            first = false;
            if (leaf(child, count)) {
                if constexpr (AnyHit) return;
                tbox = simd::box_tfar(tfar);
                r.tbox = WideLane<N>(tbox);
            }
        }
        if (!pop()) return;
    }
}
}  // namespace detail

/// Walks the subtree (child, count) of `layout` (the root is (0, 0)) for ray `r`. `tfar` is the
/// scalar copy of the ray's far distance: `leaf(first_block, count)` tests a leaf, and when it finds
/// a hit it lowers both `tfar` and r.tfar and returns true; with AnyHit that ends the walk. r.tbox
/// must be box_tfar(tfar) (ray_box.h) when the walk starts; the walk keeps it so. A node's
/// hit children go on the stack in the node's order for the ray's octant (wide_order.h), the
/// nearest on top, which is popped next; a popped entry farther than tfar is skipped. `stack` holds
/// layout.stack_size() entries. The caller checks that the ray is traceable (r.traceable) and the
/// layout not empty.
template <bool AnyHit, bool Plain = false, std::size_t N, class LeafFn>
inline void traverse_wide(const WideLayout<N>& layout, simd::WideRay<WideLane<N>>& r, const float& tfar,
                          WideStack& stack, std::uint32_t child, std::uint32_t count, LeafFn&& leaf) {
    detail::walk_wide<AnyHit, Plain, false>(layout, r, tfar, stack, child, count, 0, WideLane<N>(0.0f), 0, nullptr, leaf);
}

/// The same walk from the root, with the root's test already done (test_root, wide_root.h, for a
/// group of rays at once): the walk visits (child, count) first, with the root's hit children
/// `root_rest` (entry distances `root_t`) deferred, as the root's own test would have left it;
/// when (child, count) is a node, its test is done too (`first_bits`, `first_t`: RootTests::bits2
/// and t2) and the walk goes on from its outcome. The nodes and leaves visited, in the same order,
/// and the hits are those of traverse_wide from (0, 0).
template <bool AnyHit, bool Plain = false, std::size_t N, class LeafFn>
inline void traverse_wide_root(const WideLayout<N>& layout, simd::WideRay<WideLane<N>>& r, const float& tfar,
                               WideStack& stack, std::uint32_t child, std::uint32_t count, std::uint32_t root_rest,
                               const WideLane<N>& root_t, std::uint32_t first_bits, const float* first_t, LeafFn&& leaf) {
    detail::walk_wide<AnyHit, Plain, true>(layout, r, tfar, stack, child, count, root_rest, root_t, first_bits, first_t, leaf);
}

}  // namespace arbor::accel
