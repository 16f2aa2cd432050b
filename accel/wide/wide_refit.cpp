#include "accel/wide/wide_refit.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "accel/wide/wide_order.h"

namespace arbor::accel {

namespace {

/// The box of children [0, children) of `node`.
template <std::size_t N>
Bounds node_box(const WideNode<N>& node) {
    Bounds b;
    for (std::size_t c = 0; c < node.children; ++c) b.grow(Bounds{node.boxes.lo(c), node.boxes.hi(c)});
    return b;
}

/// Rewrites the vertices of the leaf's blocks [first, first + blocks) from `tris`; returns the box
/// of its triangles (padding lanes, id invalid_prim, stay NaN and add nothing).
template <std::size_t N>
Bounds refit_leaf(WideLayout<N>& layout, const TriangleView& tris, std::uint32_t first, std::uint32_t blocks) {
    Bounds box;
    for (std::uint32_t b = first; b < first + blocks; ++b) {
        WideBlock<N>& block = layout.blocks[b];
        // The block's vertex numbers first, then its vertices: each pass's loads are independent
        // of one another (a block's triangles lie anywhere in the caller's arrays: cache misses,
        // which overlap this way instead of queueing behind each lane's index load).
        std::uint32_t corner[N][3];
        std::uint32_t live = 0;
        for (std::size_t l = 0; l < N; ++l) {
            const std::uint32_t tri = block.ids[l];
            if (tri == invalid_prim) continue;
            live |= 1u << l;
            for (int c = 0; c < 3; ++c) corner[l][c] = tris.indices[3 * std::size_t(tri) + std::size_t(c)];
        }
        for (std::size_t l = 0; l < N; ++l) {
            if (!(live >> l & 1u)) continue;
            const Vec3f v0 = tris.vertex(corner[l][0]), v1 = tris.vertex(corner[l][1]), v2 = tris.vertex(corner[l][2]);
            block.tris.set(l, v0, v1, v2);
            box.grow(v0), box.grow(v1), box.grow(v2);
        }
    }
    return box;
}

}  // namespace

template <std::size_t N>
double refit_wide_layout(WideLayout<N>& layout, const TriangleView& tris) {
    if (layout.empty()) return 0.0;
    const std::size_t nodes = layout.nodes.size();
    // Leaf children first, every node on its own (each block belongs to one leaf).
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nodes, 64), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            WideNode<N>& node = layout.nodes[i];
            for (std::size_t c = 0; c < node.children; ++c) {
                if (!node.is_leaf(c)) continue;
                const Bounds box = refit_leaf(layout, tris, node.child[c], wide_blocks<N>(node.count[c]));
                node.boxes.set(c, box.lo, box.hi);
            }
        }
    });
    // Then node children, children before parents: nodes are stored depth-first (pre-order), so
    // every child node comes after its parent and a backward pass sees it first.
    for (std::size_t i = nodes; i-- > 0;) {
        WideNode<N>& node = layout.nodes[i];
        for (std::size_t c = 0; c < node.children; ++c) {
            if (node.is_leaf(c)) continue;
            const Bounds box = node_box(layout.nodes[node.child[c]]);
            node.boxes.set(c, box.lo, box.hi);
        }
    }
    make_octant_orders(layout);
    return wide_sah_cost(layout);
}

template <std::size_t N>
double wide_sah_cost(const WideLayout<N>& layout) {
    if (layout.empty()) return 0.0;
    const double root = node_box(layout.nodes[0]).area();
    if (!(root > 0.0) || !std::isfinite(root)) return 0.0;
    // The root's own test counts like every node's: its box is the root box.
    double cost = 0.0;
    for (std::size_t i = 0; i < layout.nodes.size(); ++i) {
        const WideNode<N>& node = layout.nodes[i];
        cost += node_box(node).area();
        for (std::size_t c = 0; c < node.children; ++c)
            if (node.is_leaf(c))
                cost += Bounds{node.boxes.lo(c), node.boxes.hi(c)}.area() * double(wide_blocks<N>(node.count[c]));
    }
    return cost / root;
}

template double refit_wide_layout<4>(WideLayout<4>&, const TriangleView&);
template double refit_wide_layout<8>(WideLayout<8>&, const TriangleView&);
template double refit_wide_layout<16>(WideLayout<16>&, const TriangleView&);
template double wide_sah_cost<4>(const WideLayout<4>&);
template double wide_sah_cost<8>(const WideLayout<8>&);
template double wide_sah_cost<16>(const WideLayout<16>&);

}  // namespace arbor::accel
