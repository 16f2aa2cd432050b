#pragma once
/// All hits and closest points on the kd-tree.
///
/// All hits: the rope walk of kdtree_traverse.h with a leaf that keeps every hit and never stops
/// the walk (best_t stays +inf), so every leaf along [tnear, tfar] is tested, with the tolerance
/// visits around edges and corners. A triangle referenced by several leaves is found by the same
/// test each time (same t): the caller drops the repeats (sort_unique_hits).
///
/// Closest point: depth-first over the nodes with each node's cell (the scene box cut by the
/// split planes on the way), the nearer child first, cells farther than the bound pruned. A
/// triangle may reach a hair beyond the cells that reference it (its clipped bounds are computed
/// in float), so cells are grown by 2^-16 of the scene's coordinate scale before pruning: far
/// more than that rounding, and small enough to prune as well as exact cells do.
#include "accel/core/all_hits.h"
#include "accel/core/closest_point.h"
#include "accel/kdtree/kdtree_traverse.h"
#include "simd/ray_triangle.h"

#include <algorithm>
#include <vector>

namespace arbor::accel {

/// Appends the hits of ray `ray` in `tree` to `out`: unsorted, a triangle possibly repeated.
inline void all_hits_kdtree(const KdTree& tree, const Ray& ray, std::vector<Hit>& out) {
    if (!ray_is_traceable(ray)) return;
    const simd::WoopShear shear = simd::woop_shear(ray.dir);
    const float never = std::numeric_limits<float>::infinity();
    std::uint64_t visited = 0;
    const auto leaf_fn = [&](std::uint32_t leaf_index) {
        const KdLeaf& leaf = tree.leaves[leaf_index];
        for (std::uint32_t i = leaf.first, end = leaf.first + leaf.count; i < end; ++i) {
            const KdTriangle& tri = tree.tris[tree.refs[i]];
            const simd::TriHit<float> h = simd::woop_test(ray.org, shear, ray.tnear, ray.tfar, tri.v0, tri.v1, tri.v2);
            if (h.hit) out.push_back({h.t, tri.prim, h.u, h.v});
        }
        return false;
    };
    kd::walk_ropes<false>(tree, ray, never, leaf_fn, visited);
}

/// Searches `tree` for the closest point to s.p within the bound s was made with.
inline void closest_point_kdtree(const KdTree& tree, PointSearch& s) {
    if (tree.empty() || !s.searchable()) return;
    struct Entry {
        std::uint32_t node;
        float dist2;
        Bounds cell;
    };
    float scale = 0.0f;
    for (int k = 0; k < 3; ++k)
        scale = std::max({scale, std::fabs(tree.box.lo[k]), std::fabs(tree.box.hi[k]), tree.box.hi[k] - tree.box.lo[k]});
    const float tol = scale * 0x1p-16f;
    const Vec3f p = s.pf;
    const auto dist2 = [&](const Bounds& b) {
        return point_box_dist2<float>(p.x, p.y, p.z, b.lo.x - tol, b.lo.y - tol, b.lo.z - tol, b.hi.x + tol, b.hi.y + tol,
                                      b.hi.z + tol);
    };
    Entry stack[2 * kd_max_depth + 4];
    std::size_t sp = 0;
    stack[sp++] = {0, dist2(tree.box), tree.box};
    while (sp != 0) {
        const Entry e = stack[--sp];
        if (e.dist2 > s.prune_bound()) continue;
        const KdNode n = tree.nodes[e.node];
        if (n.is_leaf()) {
            const KdLeaf& leaf = tree.leaves[n.index()];
            for (std::uint32_t i = leaf.first, end = leaf.first + leaf.count; i < end; ++i) {
                const KdTriangle& tri = tree.tris[tree.refs[i]];
                if (triangle_box_dist2(p, tri.v0, tri.v1, tri.v2) <= s.prune_bound()) s.offer(tri.v0, tri.v1, tri.v2, tri.prim);
            }
            continue;
        }
        const int k = n.axis();
        Entry left{e.node + 1, 0.0f, e.cell}, right{n.index(), 0.0f, e.cell};
        left.cell.hi[k] = n.split;
        right.cell.lo[k] = n.split;
        left.dist2 = dist2(left.cell);
        right.dist2 = dist2(right.cell);
        const bool left_first = p[k] <= n.split;  // the side of the point: visited first
        const Entry& first = left_first ? left : right;
        const Entry& second = left_first ? right : left;
        if (second.dist2 <= s.prune_bound()) stack[sp++] = second;
        if (first.dist2 <= s.prune_bound()) stack[sp++] = first;
    }
}

}  // namespace arbor::accel
