#pragma once
/// The packet traversal of WideLayout<N> (TracePath::packet) for coherent rays: a RayPacket of
/// lanes<P> rays (8 or 16) walks the tree together. At a node every child box is tested against
/// all lanes still interested in the node (simd::packet_box, the same conservative slab test and
/// zero-direction rule as every other path); when all lanes share a direction octant the hit
/// children are visited in the node's order for that octant (wide_order.h, as on the single path:
/// no per-child minimum over the lanes, no sort; 1.02-1.07x on primary and shadow rays), else
/// nearest first by the smallest entry distance over the lanes; deferred ones wait on a stack that
/// keeps each lane's entry distance, so a lane drops out of a subtree once its hit is closer. When few lanes remain at a
/// node, each continues alone with the single-ray traversal from that node (`single`): the packet
/// would test boxes for lanes that are not there. Before the per-lane box tests, one N-wide test of
/// the packet's interval bounds against all children (simd/packet_bounds.h, exactly conservative)
/// drops the children that no lane can hit. Any hit: a lane that found a hit is done, and the
/// walk ends as soon as every lane is done; the hit children are visited in the reverse order,
/// farthest first (shadow rays leave a surface, and what blocks them tends to lie nearer the light
/// than the origin: 0.64-1.00x the packet triangle tests of nearest first, 0.87x in total, on 48
/// shadow views of four models; Embree's occluded packets
/// take the children in node order). See Wald et al., "Interactive Rendering with Coherent
/// Ray Tracing", EG 2001 (packets), and Benthin et al., "Combining Single and Packet-Ray Tracing
/// for Arbitrary Ray Distributions on the Intel MIC Architecture", TVCG 2012 (switching to single rays).
#include <bit>
#include <type_traits>

#include "accel/wide/wide_layout.h"
#include "accel/wide/wide_traverse.h"
#include "simd/box_kernels.h"
#include "simd/lane_order.h"
#include "simd/packet_bounds.h"

namespace arbor::accel {

/// A deferred child of the packet walk: its reference and each lane's entry distance (NaN in lanes
/// that missed it, so that no comparison brings them back).
template <class P> struct PacketStackEntry {
    P t;
    std::uint32_t child, count;
};

/// The child boxes of `n` as the packet walk reads them (CompactNode: compact_traverse.h).
template <std::size_t N>
ARBOR_INLINE const simd::BoxesSoA<N>& node_boxes(const WideNode<N>& n) {
    return n.boxes;
}

/// The bits of `hits` (one per node lane) in the order `order` (N lanes, far to near; wide_order.h):
/// bit j is set when lane order[j] is in `hits`.
template <std::size_t N> inline std::uint32_t ordered_bits(std::uint32_t hits, const std::uint8_t* order) {
#if XSIMD_WITH_AVX512F
    if constexpr (N == 16) {
        // (The maskz forms with every lane set: GCC 12 warns of the plain forms' undefined source.)
        constexpr __mmask16 all = 0xffff;
        const __m512i perm = _mm512_maskz_cvtepu8_epi32(all, _mm_loadu_si128(reinterpret_cast<const __m128i*>(order)));
        return _mm512_movepi32_mask(_mm512_maskz_permutexvar_epi32(all, perm, _mm512_movm_epi32(__mmask16(hits))));
    }
#endif
    std::uint32_t bits = 0;
    for (std::size_t j = 0; j < N; ++j) bits |= ((hits >> order[j]) & 1u) << j;
    return bits;
}

/// The direction octant (ray_octant) that the active lanes of `p` share, or -1 when they do not
/// share one (or there are none).
template <class P>
inline int packet_octant(const simd::RayPacket<P>& p) {
    const std::uint32_t active = simd::to_bits(p.active);
    if (active == 0) return -1;
    int octant = 0;
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t neg = simd::to_bits(p.near_is_hi[k]) & active;
        if (neg != 0 && neg != active) return -1;
        octant |= int(neg != 0) << k;
    }
    return octant;
}

/// Walks `layout` from the root with packet `p`, whose active lanes `bounds` bounds
/// (simd::packet_bounds). `leaf(first_block, count, lanes)` tests a leaf
/// for the lanes in the bit mask `lanes` and lowers p.tfar where it finds closer hits; it returns
/// the lanes that found a hit. `single(lane, child, count)` traces one lane alone through the
/// subtree (child, count) (lowering p.tfar in that lane on a hit) and returns whether it hit.
/// With AnyHit a lane that hit is done (removed from p.active, p.tfar = -inf). `switch_lanes`: at
/// a node reached by at most this many lanes they go on alone. `octant`: the direction octant
/// every active lane shares (ray_octant), whose per-node order (wide_order.h) then ranks a node's
/// hit children, as on the single path; -1: they are sorted by their smallest entry distance over
/// the lanes. Closest hit visits them nearest first, any hit farthest first. `stack` holds
/// layout.stack_size() entries.
/// `Layout` is WideLayout<N> or CompactLayout<N> (compact_traverse.h): the walk reads its `nodes`
/// and `orders` and a node's child boxes through node_boxes, overloaded per node type.
template <bool AnyHit, class Layout, class P, class LeafFn, class SingleFn, std::size_t N = Layout::width>
inline void traverse_packet(const Layout& layout, simd::RayPacket<P>& p, const simd::PacketBounds& bounds,
                            PacketStackEntry<P>* stack, int switch_lanes, int octant, LeafFn&& leaf,
                            SingleFn&& single) {
    using Node = std::remove_cvref_t<decltype(layout.nodes[0])>;
    std::uint32_t lanes = simd::to_bits(p.active);
    if (lanes == 0 || layout.empty()) return;
    const Node* nodes = layout.nodes.data();
    const std::uint8_t* orders = layout.orders.data() + std::size_t(octant < 0 ? 0 : octant) * N;
    const P inf(INFINITY), nan(NAN);
    std::size_t sp = 0;
    std::uint32_t child = 0, count = 0;
    // Whether some lane may reach behind its origin: only then can a tfar drop below zero, where a
    // popped entry needs slab_test's room for negative exits (slab_accept); else the plain compare.
    const bool behind = simd::to_bits((p.tnear < P(0.0f)) & p.active) != 0;
    // The box tests (packet_box, bounds_boxes, the pop rule) cull against p.tbox, box_tfar of
    // each lane's tfar (ray_box.h: room for a triangle's t rounded below its box's entry), worked
    // out again only after a leaf or a single-ray walk has lowered some tfar.
    p.tbox = simd::box_tfar(p.tfar);
    // Lanes that are finished (any hit) leave `lanes` at once; the others as their tfar drops.
    const auto finish = [&](std::uint32_t done) {
        if constexpr (AnyHit) {
            const auto m = simd::from_bits<P>(done);
            p.active = p.active & !m;
            p.tfar = simd::select(m, P(-INFINITY), p.tfar);
        }
        if (done != 0) p.tbox = simd::box_tfar(p.tfar);
        return done;
    };
    for (;;) {
        if (std::popcount(lanes) <= switch_lanes) {
            std::uint32_t done = 0;
            for (std::uint32_t l = lanes; l != 0; l &= l - 1) {
                const int i = std::countr_zero(l);
                if (single(i, child, count)) done |= 1u << i;
            }
            finish(done);
            if (AnyHit && simd::to_bits(p.active) == 0) return;
        } else if (count == 0) {
            const Node& n = nodes[child];
            // (A WideNode's own boxes, by reference; a CompactNode's decoded once for all lanes.)
            const simd::BoxesSoA<N>& boxes = node_boxes(n);
            const auto live = simd::from_bits<P>(lanes);
            alignas(64) float tmin[N];
            P tc[N];
            std::uint32_t lanes_of[N];
            std::uint32_t hit_children = 0;
            const bool by_distance = octant < 0;
            const float tfar_hi = -simd::hmin(simd::select(live, -p.tbox, inf));
            std::uint32_t maybe = simd::to_bits(simd::bounds_boxes<WideLane<N>>(bounds, tfar_hi, &boxes.b[0][0][0]));
            maybe &= (1u << n.children) - 1u;
            for (; maybe != 0; maybe &= maybe - 1) {
                const int c = std::countr_zero(maybe);
                const Vec3f lo = boxes.lo(c), hi = boxes.hi(c);
                P t;
                const auto m = (p.plain ? simd::packet_box_plain(p, lo, hi, t) : simd::packet_box(p, lo, hi, t)) & live;
                lanes_of[c] = simd::to_bits(m);
                if (lanes_of[c] == 0) continue;
                tc[c] = simd::select(m, t, nan);
                if (by_distance) tmin[c] = simd::hmin(simd::select(m, t, inf));
                hit_children |= 1u << c;
            }
            if (hit_children != 0 && !by_distance) {
                // The node's order for the packet's octant (wide_order.h), bit j of `ranked` its
                // j-th child from the far end. Closest hit: the nearest hit child next, the others
                // pushed far to near. Any hit: the farthest next, the others pushed near to far.
                const std::uint8_t* order = orders + std::size_t(child) * 8 * N;
                std::uint32_t ranked = ordered_bits<N>(hit_children, order);
                int next;
                if constexpr (AnyHit) {
                    next = std::countr_zero(ranked);
                    for (ranked &= ranked - 1; ranked != 0;) {
                        const int j = 31 - std::countl_zero(ranked);
                        ranked &= ~(1u << j);
                        const std::size_t c = order[j];
                        stack[sp++] = {tc[c], n.child[c], n.count[c]};
                    }
                } else {
                    next = 31 - std::countl_zero(ranked);
                    for (ranked &= ~(1u << next); ranked != 0; ranked &= ranked - 1) {
                        const std::size_t c = order[std::countr_zero(ranked)];
                        stack[sp++] = {tc[c], n.child[c], n.count[c]};
                    }
                }
                const std::size_t c = order[next];
                lanes = lanes_of[c];
                child = n.child[c], count = n.count[c];
                continue;
            }
            if (hit_children != 0) {
                // By the smallest entry distance over the lanes (order[0] the nearest): closest
                // hit nearest first, any hit farthest first, as above.
                std::uint8_t order[N];
                const int k = simd::order_hits(hit_children, static_cast<const float*>(tmin), order);
                int next;
                if constexpr (AnyHit) {
                    next = k - 1;
                    for (int j = 0; j < k - 1; ++j) stack[sp++] = {tc[order[j]], n.child[order[j]], n.count[order[j]]};
                } else {
                    next = 0;
                    for (int j = k - 1; j > 0; --j) stack[sp++] = {tc[order[j]], n.child[order[j]], n.count[order[j]]};
                }
                const std::size_t c = order[next];
                lanes = lanes_of[c];
                child = n.child[c], count = n.count[c];
                continue;
            }
        } else {
            const std::uint32_t done = finish(leaf(child, count, lanes));
            if (AnyHit && done != 0 && simd::to_bits(p.active) == 0) return;
        }
        // Pop the nearest deferred child that some lane can still use.
        for (;;) {
            if (sp == 0) return;
            const PacketStackEntry<P>& e = stack[--sp];
            lanes = simd::to_bits((behind ? simd::slab_accept(e.t, p.tbox) : e.t <= p.tbox) & p.active);
            if (lanes != 0) {
                child = e.child, count = e.count;
                break;
            }
        }
    }
}

}  // namespace arbor::accel
