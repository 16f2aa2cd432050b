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
/// candidates are found (accel/core/hit_record.h). Closest-hit queries of the single path, in its
/// groups of rays in different octants (WideBvhAccel::trace_group_shared); WideConfig::
/// shared_leaf_triangles = 0 turns it off.
#include "accel/core/ray.h"
#include "accel/wide/wide_layout.h"
#include "simd/box_kernels.h"
#include "simd/ray_packet.h"
#include "simd/tri_kernels.h"
#include "simd/wide_ray_setup.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>

namespace arbor::accel {

/// The root slots of `layout` that are leaves of at most `max_triangles` triangles
/// (WideConfig::shared_leaf_triangles; larger leaves: their rays' own block tests) and that a
/// group of `group` rays can be expected to test often enough for the pass to take them: by the
/// surface-area argument of the SAH, a ray through the root box enters a child box with
/// probability area(child) / area(root), so `group` rays give group * area(child) / area(root)
/// rays in it, of which test_shared_leaves needs as many as the leaf has triangles per block;
/// a slot is kept when the expectation reaches half that (rays that start inside the scene are
/// not rays through the root box: the groups decide, this only leaves out the hopeless slots). A
/// ground plane or a room's walls pass; the small leaves under the root of a flat model (woody,
/// the alligator's lbvh) do not, and their groups skip the box tests. As bits (0 for an empty
/// layout).
template <std::size_t N>
std::uint32_t shared_leaf_slots(const WideLayout<N>& layout, std::uint32_t max_triangles = 32, std::size_t group = 16) {
    if (layout.empty()) return 0;
    const WideNode<N>& root = layout.nodes[0];
    const auto area = [](const Vec3f& lo, const Vec3f& hi) {
        const float x = hi[0] - lo[0], y = hi[1] - lo[1], z = hi[2] - lo[2];
        return double(x) * y + double(y) * z + double(z) * x;
    };
    Vec3f rlo(INFINITY), rhi(-INFINITY);
    for (std::size_t c = 0; c < root.children; ++c) rlo = simd::vmin(rlo, root.boxes.lo(c)), rhi = simd::vmax(rhi, root.boxes.hi(c));
    const double root_area = area(rlo, rhi);
    std::uint32_t slots = 0;
    for (std::size_t c = 0; c < root.children; ++c) {
        const std::uint32_t count = root.count[c];
        if (count == 0 || count > max_triangles) continue;
        const double expected = root_area > 0.0 ? double(group) * area(root.boxes.lo(c), root.boxes.hi(c)) / root_area : double(group);
        if (2.0 * expected * wide_blocks<N>(count) >= double(count)) slots |= 1u << c;
    }
    return slots;
}

/// Per ray of a group: the closest hit found by test_shared_leaves (miss: t = +inf, invalid prim).
template <std::size_t Rays> struct SharedHits {
    alignas(64) float t[Rays], u[Rays], v[Rays];
    alignas(64) std::int32_t prim[Rays];

    Hit hit(std::size_t i) const { return {t[i], std::uint32_t(prim[i]), u[i], v[i]}; }
};

/// For each root leaf in `slots` (shared_leaf_slots): the plain rays of the group `rays` (set up
/// in `setup`, simd::wide_ray_setup) whose slab test hits its box; when they are at least
/// `min_rays` and their block tests would have been at least as many as the leaf's triangles, the
/// leaf is tested for them here, one triangle at a time, their hits kept in `out`, their far
/// distances in setup lowered to them, and the leaf's slot set in their `skip` entry (zeroed here
/// for every ray). Returns whether any leaf was tested (else `out` and setup are untouched).
template <std::size_t N, class P, std::size_t Rays>
bool test_shared_leaves(const WideLayout<N>& layout, std::uint32_t slots, std::span<const Ray> rays,
                        simd::WideRaySetup<P>& setup, std::uint32_t* skip, SharedHits<Rays>& out, unsigned min_rays = 2) {
    using S = simd::WideRaySetup<P>;
    static_assert(Rays >= S::size);
    using IntP = simd::IntOf<P>;
    const WideNode<N>& root = layout.nodes[0];
    // Plain rays only (tnear >= 0, finite normal reciprocals: WideRay::plain): the walks cull boxes
    // against box_tfar of the hit found here (ray_box.h: room for the rounding of a box's entry and
    // of a triangle's t), so no walk culls a box that holds a hit at that t or nearer, and the
    // order of the tests does not change the record.
    // Behind the origin the entries are not that tight (negative exits get slab_accept's room
    // instead), and such rays keep their own walks.
    // The box tests read the set-up's arrays (the packet's own fields, stored); the full packet,
    // with its Woop set-up, is made again only for a group that tests a leaf (made for every
    // group, the alligator's lbvh diffuse rays, with a 1- and a 14-triangle root leaf, ran at
    // 0.84x of the pass turned off; so, 0.95x).
    simd::RayPacket<P> box;
    const auto ld = [&setup](typename S::Field k) { return simd::load_lanes<P>(setup.f[k]); };
    box.org = {ld(S::org_x), ld(S::org_y), ld(S::org_z)};
    box.rcp_near = {ld(S::rn_x), ld(S::rn_y), ld(S::rn_z)};
    box.rcp_far = {ld(S::rf_x), ld(S::rf_y), ld(S::rf_z)};
    for (int k = 0; k < 3; ++k) box.near_is_hi[k] = simd::from_bits<P>(setup.near_is_hi[k]);
    box.tnear = ld(S::tnear);
    box.tfar = ld(S::tfar);
    box.tbox = ld(S::tbox);
    const std::uint32_t active = setup.plain;  // (traceable and plain)
    box.active = simd::from_bits<P>(active);
    // The leaves to test, and for each the rays that test it.
    std::uint32_t tested = 0, lanes_of[N];
    for (std::uint32_t m = slots; m != 0; m &= m - 1) {
        const int c = std::countr_zero(m);
        P t_entry;
        const std::uint32_t lanes = simd::to_bits(simd::packet_box_plain(box, root.boxes.lo(c), root.boxes.hi(c), t_entry)) & active;
        const auto n = unsigned(std::popcount(lanes));
        // (Packet tests no more than the block tests they replace: with 1.5x as many, the
        // ground leaf of builtin:default, 4 triangles, took only groups of 6 rays or more, and
        // its random rays gained 1.05x instead of 1.13x; the tuning files, 1 thread.)
        if (n < min_rays || n * wide_blocks<N>(root.count[c]) < root.count[c]) continue;
        tested |= 1u << c;
        lanes_of[c] = lanes;
    }
    if (tested == 0) return false;
    std::fill(skip, skip + S::size, 0u);
    const simd::RayPacket<P> p = simd::load_packet<P>(rays);
    simd::PacketHit<P> rec;
    P tfar = box.tfar;
    for (std::uint32_t m = tested; m != 0; m &= m - 1) {
        const int c = std::countr_zero(m);
        const std::uint32_t count = root.count[c], first = root.child[c];
        const auto live = simd::from_bits<P>(lanes_of[c]);
        // The leaf's triangles are slots first * N .. first * N + count (its blocks are whole).
        for (std::size_t s = std::size_t(first) * N; s < std::size_t(first) * N + count; ++s) {
            const simd::TriHit<P> h =
                simd::packet_triangle<P, true>(p, tfar, layout.vertex(s, 0), layout.vertex(s, 1), layout.vertex(s, 2));
            const auto take = simd::offer_lanes<false>(rec, h.hit & live, h.t, IntP(std::int32_t(layout.prim(s))), h.u, h.v);
            tfar = simd::select(take, h.t, tfar);
        }
        for (std::uint32_t r = lanes_of[c]; r != 0; r &= r - 1) skip[std::countr_zero(r)] |= 1u << c;
    }
    simd::store_lanes(tfar, setup.f[S::tfar]);
    simd::store_lanes(simd::box_tfar(tfar), setup.f[S::tbox]);
    simd::store_lanes(rec.t, out.t);
    simd::store_lanes(rec.u, out.u);
    simd::store_lanes(rec.v, out.v);
    simd::store_lanes(rec.prim, out.prim);
    return true;
}

}  // namespace arbor::accel
