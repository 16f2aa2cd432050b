#pragma once
/// The root test of the single-ray walk, done for a group of rays before any of them walks on.
///
/// Every ray's walk starts with the same node, and on small scenes that node is most of the walk
/// (held-out random rays: 1.3-2.0 node tests and 0.5-0.8 leaf blocks per ray on builtin:default,
/// woody and the alligator, perf/results/heldout-2026-12-03.md). Tested inside the walk, the root is
/// a chain of dependent steps (the ray's constants, the node's loads, the slab test, the hit mask,
/// the branch on one hit child or more) that the core cannot start before the previous ray's walk
/// has ended, mispredicted branches included. Tested here, one ray after another with no branch on
/// the outcome, the roots of a group overlap in the core's window; each walk then begins from its
/// ray's stored result (traverse_wide_root, wide_traverse.h): the root's hit children pushed in
/// the octant's order and the nearest popped, as the walk would have done.
#include "accel/wide/wide_traverse.h"
#include "simd/wide_ray_setup.h"

#include <bit>
#include <cmath>
#include <cstdint>

namespace arbor::accel {

/// Per ray of a group of up to `Rays`: the root's hit children and their entry distances.
template <std::size_t N, std::size_t Rays> struct RootTests {
    alignas(64) float t[Rays][N];
    std::uint32_t bits[Rays];

    WideLane<N> entry(std::size_t i) const { return simd::load_lanes<WideLane<N>>(t[i]); }
};

/// The root test of rays [0, count) of `setup` (a group set up by simd::wide_ray_setup): per ray
/// the box form its walk takes (WideRay::plain), so bits and distances are those of the walk's own
/// root test; rays that are not traceable hit no child. When a ray hits one child only, its
/// distances are stored as -inf: the walk goes on to a lone hit child without checking its
/// distance against tfar (traverse_wide), and so, by the pop that then always accepts it, does
/// traverse_wide_root.
template <std::size_t N, class P, std::size_t Rays>
inline void test_root(const WideLayout<N>& layout, const simd::WideRaySetup<P>& setup, std::size_t count,
                      RootTests<N, Rays>& out) {
    static_assert(Rays >= simd::WideRaySetup<P>::size);
    using T = WideLane<N>;
    const float* soa = &layout.nodes[0].boxes.b[0][0][0];
    for (std::size_t i = 0; i < count; ++i) {
        simd::WideRay<T> r;
        setup.get(i, r);
        T t;
        const std::uint32_t bits =
            simd::to_bits(r.plain ? simd::ray_boxes_plain<T>(r, soa, t) : simd::ray_boxes<T>(r, soa, t));
        const std::uint32_t kept = r.traceable ? bits : 0u;
        const bool lone = std::has_single_bit(kept);
        t = simd::select(simd::from_bits<T>(lone ? ~0u : 0u), T(-INFINITY), t);
        simd::store_lanes(t, out.t[i]);
        out.bits[i] = kept;
    }
}

}  // namespace arbor::accel
