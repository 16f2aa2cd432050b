#pragma once
/// All hits and closest points on the scalar layout Bvh2Layout (the BVHs built for the reference
/// path only), the same walks as wide_queries.h does on the SIMD layout: all hits through the
/// reference loop of bvh2_traverse.h with a leaf that keeps every hit, closest points depth-first
/// over the two child boxes of a node, the nearer visited first.
#include "accel/core/all_hits.h"
#include "accel/bvh/bvh2_traverse.h"
#include "accel/core/closest_point.h"
#include "simd/ray_triangle.h"

#include <vector>

namespace arbor::accel {

/// Appends every hit of ray `ray` (traceable) in `layout` to `out` (unsorted, each triangle once).
inline void all_hits_bvh2(const Bvh2Layout& layout, const Ray& ray, std::span<Bvh2StackEntry> stack, std::vector<Hit>& out) {
    const simd::WoopShear shear = simd::woop_shear(ray.dir);
    float tfar = ray.tfar;
    auto leaf = [&](std::uint32_t first, std::uint32_t count) {
        for (std::uint32_t s = first; s < first + count; ++s) {
            const simd::TriHit<float> h =
                simd::woop_test(ray.org, shear, ray.tnear, ray.tfar, layout.vertex(s, 0), layout.vertex(s, 1), layout.vertex(s, 2));
            if (h.hit) out.push_back({h.t, layout.prim_ids[s], h.u, h.v});
        }
        return false;
    };
    traverse_bvh2<false>(layout, ray.org, ray.dir, ray.tnear, tfar, stack, leaf);
}

/// Searches `layout` for the closest point to s.p within the bound s was made with.
inline void closest_point_bvh2(const Bvh2Layout& layout, PointSearch& s, std::vector<Bvh2StackEntry>& stack) {
    if (layout.empty() || !s.searchable()) return;
    stack.resize(std::size_t(layout.max_depth) + 2);
    const Vec3f p = s.pf;
    const auto leaf = [&](std::uint32_t first, std::uint32_t count) {
        for (std::uint32_t i = first; i < first + count; ++i) {
            const Vec3f a = layout.vertex(i, 0), b = layout.vertex(i, 1), c = layout.vertex(i, 2);
            if (triangle_box_dist2(p, a, b, c) <= s.prune_bound()) s.offer(a, b, c, layout.prim_ids[i]);
        }
    };
    if (layout.root_count != 0) {
        leaf(layout.root_child, layout.root_count);
        return;
    }
    std::size_t sp = 0;
    stack[sp++] = {0, 0, 0.0f};  // t holds the box's squared distance here
    while (sp != 0) {
        const Bvh2StackEntry e = stack[--sp];
        if (e.t > s.prune_bound()) continue;
        if (e.count != 0) {
            leaf(e.child, e.count);
            continue;
        }
        const Bvh2Node& n = layout.nodes[e.child];
        float d[2];
        for (int c = 0; c < 2; ++c)
            d[c] = point_box_dist2<float>(p.x, p.y, p.z, n.x[c], n.y[c], n.z[c], n.x[2 + c], n.y[2 + c], n.z[2 + c]);
        const int near = d[1] < d[0] ? 1 : 0, far = 1 - near;
        if (d[far] <= s.prune_bound()) stack[sp++] = {n.child[far], n.count[far], d[far]};
        if (d[near] <= s.prune_bound()) stack[sp++] = {n.child[near], n.count[near], d[near]};
    }
}

}  // namespace arbor::accel
