#pragma once
/// The root test of the single-ray walk, done for a group of rays before any of them walks on.
///
/// Every ray's walk starts with the same node, and on small scenes that node is most of the walk
/// (held-out random rays: 1.3-2.0 node tests and 0.5-0.8 leaf blocks per ray on builtin:default,
/// woody and the alligator). Tested inside the walk, the root is
/// a chain of dependent steps (the ray's constants, the node's loads, the slab test, the hit mask,
/// the branch on one hit child or more) that the core cannot start before the previous ray's walk
/// has ended, mispredicted branches included. Tested here, one ray after another with no branch on
/// the outcome, the roots of a group overlap in the core's window; each walk then begins from its
/// ray's stored result (traverse_wide_root, wide_traverse.h): the first child to visit at once,
/// the other hit children pushed in the octant's order, as the walk would have left them.
#include "accel/wide/wide_packet.h"
#include "accel/wide/wide_traverse.h"
#include "simd/wide_ray_setup.h"

#include <bit>
#include <cmath>
#include <cstdint>

namespace arbor::accel {

/// Whether the traceable rays of a set-up group do not all share one direction octant (the single
/// paths take the group's root tests first for such groups).
template <class P>
inline bool mixed_octants(const simd::WideRaySetup<P>& s) {
    bool mixed = false;
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t neg = s.near_is_hi[k] & s.traceable;
        mixed |= neg != 0 && neg != s.traceable;
    }
    return mixed;
}

/// Per ray of a group of up to `Rays`: where its walk starts after the root. The first child it
/// visits (child, count; `live` false: none, the walk ends) and the other hit children it defers
/// (`rest`, with their entry distances t), as the walk's own root test would have left them; and
/// when that first child is a node (count == 0), that node's test too (`bits2`, distances `t2`),
/// which the walk takes instead of testing the node itself (unset for other rays).
template <std::size_t N, std::size_t Rays> struct RootTests {
    alignas(64) float t[Rays][N];
    std::uint32_t rest[Rays];
    std::uint32_t child[Rays];
    std::uint32_t count[Rays];
    bool live[Rays];
    /// The test of the first child when it is a node (else of the root again, unused): its hit
    /// children and their distances, which the walk takes instead of testing it itself.
    alignas(64) float t2[Rays][N];
    std::uint32_t bits2[Rays];

    WideLane<N> entry(std::size_t i) const { return simd::load_lanes<WideLane<N>>(t[i]); }
};

/// The root test of rays [0, count) of `setup` (a group set up by simd::wide_ray_setup), straight
/// from the group's arrays: per ray the slab test its walk takes (slab_test_plain for rays with
/// WideRay::plain set, else slab_test: the operations of ray_boxes_plain / ray_boxes on the same
/// operands, so the same hit children and distances); rays that are not traceable hit none. Then
/// what the walk would do next, without a branch: one hit child is visited whatever its distance;
/// of several, the children pushed in the root's order for the ray's octant (wide_order.h) and
/// popped nearest first, those beyond box_tfar of the ray's tfar (by slab_accept, the walk's pop
/// rule: room for rounding and a negative tfar) would be popped and skipped (tfar only drops), so the first is the
/// nearest in that order within tfar, and the others within tfar are the deferred ones. Then, for the rays whose first
/// child is a node, that node's test (the walk's first step, with the same operands: no hit can have lowered tfar
/// before it): the group's tests are independent, so they overlap, while in the walk the node's loads and slab test
/// were a chain of their own at the head of each ray. Only the test moves here; what the walk does with its outcome
/// (one child or several, push, pop) stays in the walk, on predicted branches (done here as well, branch-free, it cost
/// more than it saved: 0.86x on random rays).
///
/// Skip: `skip` holds per ray the root children its walk must not visit (their leaves were
/// tested for it already, test_shared_leaves in wide_shared_leaves.h); they count as missed.
///
/// `Layout` is WideLayout<N> or CompactLayout<N>: a node's boxes are read through node_boxes
/// (wide_packet.h; a compact node's decoded as its walk decodes them, the root's once per group).
template <bool Skip = false, class Layout, class P, std::size_t Rays, std::size_t N = Layout::width>
__attribute__((noinline)) void test_root(const Layout& layout, const simd::WideRaySetup<P>& setup, std::size_t count,
                                         RootTests<N, Rays>& out, const std::uint32_t* skip = nullptr) {
    using S = simd::WideRaySetup<P>;
    static_assert(Rays >= S::size);
    using T = WideLane<N>;
    constexpr std::size_t n = N;
    const auto& root = layout.nodes[0];
    const simd::BoxesSoA<N>& root_boxes = node_boxes(root);
    // Ray i's slab test of the node whose boxes are at `soa`: the hit bits, distances in t.
    const auto test = [&setup](std::size_t i, const float* soa, T& t) {
        const auto v = [&setup, i](typename S::Field k) { return T(setup.f[k][i]); };
        const simd::Vec3<T> org{v(S::org_x), v(S::org_y), v(S::org_z)};
        const simd::Vec3<T> rcp_near{v(S::rn_x), v(S::rn_y), v(S::rn_z)};
        const simd::Vec3<T> rcp_far{v(S::rf_x), v(S::rf_y), v(S::rf_z)};
        // (Against box_tfar of the ray's tfar, ray_box.h, as the walk's box tests.)
        const T tnear = v(S::tnear), tfar = v(S::tbox);
        simd::Vec3<T> near_plane, far_plane;
        for (int k = 0; k < 3; ++k) {
            const std::size_t hi = (setup.near_is_hi[k] >> i) & 1u;
            near_plane[k] = simd::load_lanes<T>(soa + (hi * 3 + std::size_t(k)) * n);
            far_plane[k] = simd::load_lanes<T>(soa + ((1 - hi) * 3 + std::size_t(k)) * n);
        }
        return simd::to_bits(((setup.plain >> i) & 1u)
                                 ? simd::slab_test_plain<T>(near_plane, far_plane, org, rcp_near, rcp_far, tnear, tfar, t)
                                 : simd::slab_test<T>(near_plane, far_plane, org, rcp_near, rcp_far, tnear, tfar, t));
    };
    std::uint32_t deeper = 0;  // rays whose first child is a node
    for (std::size_t i = 0; i < count; ++i) {
        int near_is_hi[3];
        for (int k = 0; k < 3; ++k) near_is_hi[k] = int((setup.near_is_hi[k] >> i) & 1u);
        T t;
        const std::uint32_t bits = test(i, &root_boxes.b[0][0][0], t);
        // (Masks and |1 instead of conditions: as branches, they were mispredicted on incoherent
        // rays, and made the group's root tests cost three times as much.)
        std::uint32_t hit = bits & (0u - ((setup.traceable >> i) & 1u));
        if constexpr (Skip) hit &= ~skip[i];
        const std::uint32_t lone = 0u - std::uint32_t(std::popcount(hit) == 1);
        // The walk's pop rule, slab_accept(t, tfar), with its bound worked out once per ray in scalar
        // (the same operations: bit-identical; as a vector it cost 5% on random rays).
        const std::uint32_t live = hit & (simd::to_bits(t <= T(simd::slab_accept_bound(setup.f[S::tbox][i]))) | lone);
        const std::uint8_t* order = layout.orders.data() + std::size_t(ray_octant(near_is_hi)) * N;
        const std::uint32_t ranked = ordered_bits<N>(live, order);
        const unsigned first = order[31 - std::countl_zero(ranked | 1u)];  // (order[0] when none)
        simd::store_lanes(t, out.t[i]);
        out.rest[i] = live & ~(1u << first);
        out.child[i] = root.child[first];
        out.count[i] = root.count[first];
        out.live[i] = live != 0;
        out.bits2[i] = 0;  // (set below for a node; a walk from a leaf never reads it)
        deeper |= std::uint32_t(live != 0 && root.count[first] == 0) << i;
    }
    // Then the first child's own test for the rays whose first child is a node, one after another
    // (independent of each other, so they overlap), the same operations on the same operands as
    // the walk's test of that node: the walk takes the outcome instead (first_bits, first_t).
    for (std::uint32_t m = deeper; m != 0; m &= m - 1) {
        const std::size_t i = std::size_t(std::countr_zero(m));
        T t2;
        const simd::BoxesSoA<N>& boxes = node_boxes(layout.nodes[out.child[i]]);
        out.bits2[i] = test(i, &boxes.b[0][0][0], t2);
        simd::store_lanes(t2, out.t2[i]);
    }
}

}  // namespace arbor::accel
