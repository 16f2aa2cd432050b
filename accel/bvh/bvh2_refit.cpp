#include "accel/bvh/bvh2_refit.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

namespace arbor::accel {

namespace {

Bounds child_box(const Bvh2Node& n, int c) {
    return {{n.x[c], n.y[c], n.z[c]}, {n.x[2 + c], n.y[2 + c], n.z[2 + c]}};
}

void set_child_box(Bvh2Node& n, int c, const Bounds& b) {
    n.x[c] = b.lo.x, n.y[c] = b.lo.y, n.z[c] = b.lo.z;
    n.x[2 + c] = b.hi.x, n.y[2 + c] = b.hi.y, n.z[2 + c] = b.hi.z;
}

Bounds node_box(const Bvh2Node& n) {
    Bounds b = child_box(n, 0);
    b.grow(child_box(n, 1));
    return b;
}

/// Writes slot `slot`'s vertices (of triangle prim_ids[slot]) from `tris`; returns its box.
Bounds refit_slot(Bvh2Layout& layout, const TriangleView& tris, std::uint32_t slot) {
    TriBlock4& b = layout.blocks[slot / tri_block_width];
    const std::uint32_t l = slot % tri_block_width;
    const std::uint32_t tri = layout.prim_ids[slot];
    float (*dst[3])[4] = {b.v0, b.v1, b.v2};
    Bounds box;
    for (int v = 0; v < 3; ++v) {
        const Vec3f p = tris.corner(tri, v);
        dst[v][0][l] = p.x, dst[v][1][l] = p.y, dst[v][2][l] = p.z;
        box.grow(p);
    }
    return box;
}

Bounds refit_leaf(Bvh2Layout& layout, const TriangleView& tris, std::uint32_t first, std::uint32_t count) {
    Bounds box;
    for (std::uint32_t s = first; s < first + count; ++s) box.grow(refit_slot(layout, tris, s));
    return box;
}

}  // namespace

double refit_bvh2_layout(Bvh2Layout& layout, const TriangleView& tris) {
    if (layout.empty()) return 0.0;
    if (layout.root_count > 0) {  // a tiny scene: the root is a leaf
        layout.root_box = refit_leaf(layout, tris, layout.root_child, layout.root_count);
    } else {
        const std::size_t nodes = layout.nodes.size();
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nodes, 256), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                Bvh2Node& n = layout.nodes[i];
                for (int c = 0; c < 2; ++c)
                    if (n.is_leaf(c)) set_child_box(n, c, refit_leaf(layout, tris, n.child[c], n.count[c]));
            }
        });
        // Depth-first order puts every child node after its parent: backwards, children come first.
        for (std::size_t i = nodes; i-- > 0;) {
            Bvh2Node& n = layout.nodes[i];
            for (int c = 0; c < 2; ++c)
                if (!n.is_leaf(c)) set_child_box(n, c, node_box(layout.nodes[n.child[c]]));
        }
        layout.root_box = node_box(layout.nodes[0]);
    }
    // The padding lanes of the last block repeat a triangle (bvh2_layout.h): rewritten as well.
    std::uint32_t slots = 0;
    if (layout.root_count > 0) slots = layout.root_child + layout.root_count;
    else
        for (const Bvh2Node& n : layout.nodes)
            for (int c = 0; c < 2; ++c)
                if (n.is_leaf(c)) slots = std::max(slots, n.child[c] + n.count[c]);
    for (std::uint32_t s = slots; s < layout.prim_ids.size(); ++s) refit_slot(layout, tris, s);
    return bvh2_sah_cost(layout);
}

double bvh2_sah_cost(const Bvh2Layout& layout) {
    if (layout.empty()) return 0.0;
    const double root = layout.root_box.area();
    if (!(root > 0.0) || !std::isfinite(root)) return 0.0;
    if (layout.root_count > 0) return double(layout.root_count);
    double cost = 0.0;
    for (const Bvh2Node& n : layout.nodes) {
        cost += node_box(n).area();
        for (int c = 0; c < 2; ++c)
            if (n.is_leaf(c)) cost += child_box(n, c).area() * double(n.count[c]);
    }
    return cost / root;
}

}  // namespace arbor::accel
