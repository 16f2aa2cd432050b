#pragma once
/// The two queries beyond closest and any hit on WideLayout<N>: every crossing along a ray
/// (all_hits_wide) and the closest point of the scene to a point (closest_point_wide).
///
/// All hits: the single-ray walk of wide_traverse.h with a leaf that keeps every hit and never
/// shortens the ray, so every leaf the ray's [tnear, tfar] passes through is tested with the same
/// SIMD triangle test as the closest-hit path. Each triangle sits in exactly one leaf of a BVH, so
/// it is reported once.
///
/// Closest point: a depth-first walk that tests the query point against the N child boxes of a
/// node at once (their float distances, closest_point.h's pruning rule), pushes the children within
/// the current bound farthest first so the nearest is visited next, and tests a leaf's triangles
/// with the exact double-precision distance. A popped entry beyond the (by then lower) bound is
/// skipped.
#include "accel/core/all_hits.h"
#include "accel/core/closest_point.h"
#include "accel/wide/wide_traverse.h"

#include <algorithm>
#include <vector>

namespace arbor::accel {

/// Appends every hit of ray `ray` in `layout` to `out` (unsorted, each triangle once).
template <std::size_t N>
void all_hits_wide(const WideLayout<N>& layout, const Ray& ray, WideStack& stack, std::vector<Hit>& out) {
    using T = WideLane<N>;
    if (layout.empty()) return;
    simd::WideRay<T> r = simd::wide_ray<T>(ray.org, ray.dir, ray.tnear, ray.tfar);
    if (!r.traceable) return;
    const WideBlock<N>* blocks = layout.blocks.data();
    auto leaf = [&](std::uint32_t first, std::uint32_t n) {
        const std::uint32_t end = first + wide_blocks<N>(n);
        for (std::uint32_t b = first; b < end; ++b) {
            const simd::TriHit<T> h = simd::ray_triangles<T, true>(r, blocks[b].soa());
            for (std::uint32_t bits = simd::to_bits(h.hit); bits != 0; bits &= bits - 1) {
                const auto l = std::size_t(std::countr_zero(bits));
                out.push_back({simd::lane(h.t, l), blocks[b].ids[l], simd::lane(h.u, l), simd::lane(h.v, l)});
            }
        }
        return false;  // the ray is never shortened: every leaf it passes is tested
    };
    const float tfar = ray.tfar;
    if (r.plain) traverse_wide<false, true>(layout, r, tfar, stack, 0, 0, leaf);
    else traverse_wide<false, false>(layout, r, tfar, stack, 0, 0, leaf);
}

/// A deferred subtree of the closest-point walk: reference (as WideNode::child / count) and the
/// float squared distance of its box.
struct PointStackEntry {
    std::uint32_t child, count;
    float dist2;
};

/// Entries the closest-point walk of `layout` may need: every node on a path pushes at most N.
template <std::size_t N> std::size_t point_stack_size(const WideLayout<N>& layout) {
    return std::size_t(layout.depth) * N + 1;
}

/// Searches `layout` for the closest point to s.p within the bound s was made with.
template <std::size_t N>
void closest_point_wide(const WideLayout<N>& layout, PointSearch& s, std::vector<PointStackEntry>& stack) {
    using T = WideLane<N>;
    if (layout.empty() || !s.searchable()) return;
    stack.resize(point_stack_size(layout));
    const T px(s.pf.x), py(s.pf.y), pz(s.pf.z);
    const WideNode<N>* nodes = layout.nodes.data();
    const WideBlock<N>* blocks = layout.blocks.data();
    std::size_t sp = 0;
    stack[sp++] = {0, 0, 0.0f};
    while (sp != 0) {
        const PointStackEntry e = stack[--sp];
        if (e.dist2 > s.prune_bound()) continue;
        if (e.count != 0) {
            const std::uint32_t end = e.child + wide_blocks<N>(e.count);
            for (std::uint32_t b = e.child; b < end; ++b) {
                const simd::TrisSoA<N>& t = blocks[b].tris;
                // The N triangles' boxes against the bound first (the same rule as the node boxes):
                // the exact double-precision test runs only for triangles that may be closer.
                T box[2][3];
                for (int k = 0; k < 3; ++k) {
                    const T a = simd::load_lanes<T>(t.v[0][k]), b1 = simd::load_lanes<T>(t.v[1][k]),
                            c = simd::load_lanes<T>(t.v[2][k]);
                    box[0][k] = simd::rmin(simd::rmin(a, b1), c);
                    box[1][k] = simd::rmax(simd::rmax(a, b1), c);
                }
                const T d2 = point_box_dist2<T>(px, py, pz, box[0][0], box[0][1], box[0][2], box[1][0], box[1][1], box[1][2]);
                const std::uint32_t used = std::min<std::uint32_t>(e.count - (b - e.child) * N, N);
                const std::uint32_t lanes = used >= 32 ? ~0u : (1u << used) - 1u;  // not the NaN padding
                for (std::uint32_t bits = simd::to_bits(d2 <= T(s.prune_bound())) & lanes; bits != 0; bits &= bits - 1) {
                    const auto l = std::size_t(std::countr_zero(bits));
                    s.offer({t.v[0][0][l], t.v[0][1][l], t.v[0][2][l]}, {t.v[1][0][l], t.v[1][1][l], t.v[1][2][l]},
                            {t.v[2][0][l], t.v[2][1][l], t.v[2][2][l]}, blocks[b].ids[l]);
                }
            }
            continue;
        }
        const WideNode<N>& n = nodes[e.child];
        const float* lo = &n.boxes.b[0][0][0];
        const float* hi = &n.boxes.b[1][0][0];
        const T d2 = point_box_dist2<T>(px, py, pz, simd::load_lanes<T>(lo), simd::load_lanes<T>(lo + N),
                                        simd::load_lanes<T>(lo + 2 * N), simd::load_lanes<T>(hi),
                                        simd::load_lanes<T>(hi + N), simd::load_lanes<T>(hi + 2 * N));
        alignas(64) float d[N];
        simd::store_lanes(d2, d);
        const std::uint32_t used = n.children >= 32 ? ~0u : (1u << n.children) - 1u;
        std::uint32_t bits = simd::to_bits(d2 <= T(s.prune_bound())) & used;
        // Push farthest first (the nearest is popped next): insertion by distance, at most N items.
        const std::size_t base = sp;
        for (; bits != 0; bits &= bits - 1) {
            const int c = std::countr_zero(bits);
            const PointStackEntry in{n.child[c], n.count[c], d[c]};
            std::size_t j = sp++;
            while (j > base && stack[j - 1].dist2 < in.dist2) {
                stack[j] = stack[j - 1];
                --j;
            }
            stack[j] = in;
        }
    }
}

}  // namespace arbor::accel
