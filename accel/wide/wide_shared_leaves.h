#pragma once
/// Leaves under the root that many rays of a group test: tested once for the group, as a packet.
///
/// Scenes with a few large triangles (a ground plane, the walls of a room) often get them as a
/// small leaf right under the root, whose box spans the scene: on incoherent rays most rays of a
/// group hit that box, and each tested the leaf's block in its own walk (builtin:default's random
/// rays: 0.48 leaf tests per ray, 0.31 of the rays hit the ground leaf's box and no other root
/// child). Tested here, one triangle at a time against the group's rays whose slab test hits the
/// leaf's box (simd::packet_triangle, as on the packet path: bit for bit the scalar test), the leaf
/// costs its triangles' tests once per group instead of a block test per ray, and rays that hit
/// nothing else under the root need no walk at all. Each such ray's far distance is lowered to its
/// hit there, the hit starts its walk's record, and the leaf is taken out of its root test
/// (test_root's `skip`): the walk then finds the closest hit of the rest, and the record keeps the
/// closer of the two by the rule of simd::closer, which does not depend on the order in which the
/// candidates are found (accel/core/hit_record.h). Closest-hit queries only.
#include "accel/wide/wide_layout.h"
#include "simd/box_kernels.h"
#include "simd/ray_packet.h"
#include "simd/tri_kernels.h"
#include "simd/wide_ray_setup.h"

#include <algorithm>
#include <bit>
#include <cstdint>

namespace arbor::accel {

/// The root slots of `layout` that are leaves of at most `max_triangles` triangles
/// (WideConfig::shared_leaf_triangles; larger leaves: their rays' own block tests), as bits (0 for
/// an empty layout).
template <std::size_t N> std::uint32_t shared_leaf_slots(const WideLayout<N>& layout, std::uint32_t max_triangles = 32) {
    if (layout.empty()) return 0;
    const WideNode<N>& root = layout.nodes[0];
    std::uint32_t slots = 0;
    for (std::size_t c = 0; c < root.children; ++c)
        if (root.count[c] != 0 && root.count[c] <= max_triangles) slots |= 1u << c;
    return slots;
}

/// Per ray of a group: the closest hit found by test_shared_leaves (miss: t = +inf, invalid prim).
template <std::size_t Rays> struct SharedHits {
    alignas(64) float t[Rays], u[Rays], v[Rays];
    alignas(64) std::int32_t prim[Rays];

    Hit hit(std::size_t i) const { return {t[i], std::uint32_t(prim[i]), u[i], v[i]}; }
};

/// For each root leaf in `slots` (shared_leaf_slots): the plain rays of packet `p` (the group set
/// up in `setup`) whose slab test hits its box; when they are at least `min_rays` and their block tests
/// would have been at least as many as the leaf's triangles, the leaf is tested for them here, one
/// triangle at a time, their hits kept in `out`, their far distances in setup lowered to them, and
/// the leaf's slot set in their `skip` entry (zeroed here for every ray). Returns whether any leaf
/// was tested (else `out` and setup are untouched).
template <std::size_t N, class P, std::size_t Rays>
bool test_shared_leaves(const WideLayout<N>& layout, std::uint32_t slots, const simd::RayPacket<P>& p,
                        simd::WideRaySetup<P>& setup, std::uint32_t* skip, SharedHits<Rays>& out, unsigned min_rays = 2) {
    using S = simd::WideRaySetup<P>;
    static_assert(Rays >= S::size);
    using IntP = simd::IntOf<P>;
    const WideNode<N>& root = layout.nodes[0];
    const WideBlock<N>* blocks = layout.blocks.data();
    // Plain rays only (tnear >= 0, finite normal reciprocals: WideRay::plain): their box entry
    // distances are never above the true ones (Ize's padding), so no walk culls a box that holds
    // a hit at the t of the one found here, and the order of the tests does not change the record.
    // Behind the origin the slab test is not that tight (a box entered at a tied negative t can
    // be culled by either order), and such rays keep their own walks.
    const std::uint32_t active = simd::to_bits(p.active & p.plain_lanes);
    simd::PacketHit<P> rec;
    P tfar = p.tfar;
    bool tested = false;
    for (std::uint32_t m = slots; m != 0; m &= m - 1) {
        const int c = std::countr_zero(m);
        const Vec3f lo{root.boxes.b[0][0][c], root.boxes.b[0][1][c], root.boxes.b[0][2][c]};
        const Vec3f hi{root.boxes.b[1][0][c], root.boxes.b[1][1][c], root.boxes.b[1][2][c]};
        P t_entry;
        const std::uint32_t lanes =
            simd::to_bits(p.plain ? simd::packet_box_plain(p, lo, hi, t_entry) : simd::packet_box(p, lo, hi, t_entry)) & active;
        const std::uint32_t count = root.count[c], first = root.child[c], nblocks = wide_blocks<N>(count);
        const auto n = unsigned(std::popcount(lanes));
        if (n < min_rays || n * nblocks < count) continue;
        if (!tested) std::fill(skip, skip + S::size, 0u);
        tested = true;
        const auto live = simd::from_bits<P>(lanes);
        for (std::uint32_t b = 0; b < nblocks; ++b) {
            const simd::TrisSoA<N>& blk = blocks[first + b].tris;
            const std::uint32_t used = std::min<std::uint32_t>(count - b * std::uint32_t(N), std::uint32_t(N));
            for (std::uint32_t l = 0; l < used; ++l) {
                const Vec3f v0{blk.v[0][0][l], blk.v[0][1][l], blk.v[0][2][l]};
                const Vec3f v1{blk.v[1][0][l], blk.v[1][1][l], blk.v[1][2][l]};
                const Vec3f v2{blk.v[2][0][l], blk.v[2][1][l], blk.v[2][2][l]};
                const simd::TriHit<P> h = simd::packet_triangle(p, tfar, v0, v1, v2);
                const auto take = simd::offer_lanes<false>(rec, h.hit & live, h.t, IntP(std::int32_t(blocks[first + b].ids[l])),
                                                            h.u, h.v);
                tfar = simd::select(take, h.t, tfar);
            }
        }
        for (std::uint32_t r = lanes; r != 0; r &= r - 1) skip[std::countr_zero(r)] |= 1u << c;
    }
    if (!tested) return false;
    simd::store_lanes(tfar, setup.f[S::tfar]);
    simd::store_lanes(rec.t, out.t);
    simd::store_lanes(rec.u, out.u);
    simd::store_lanes(rec.v, out.v);
    simd::store_lanes(rec.prim, out.prim);
    return true;
}

}  // namespace arbor::accel
