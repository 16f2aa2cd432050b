#pragma once
/// Refit of an N-wide layout (wide_layout.h): the triangles it was made over, at new positions.
///
/// The tree's topology stays: the same nodes, the same leaves holding the same triangles in the
/// same lanes. What changes is what depends on the positions: the leaves' vertex copies, every
/// child box (recomputed bottom-up: a leaf child's box is the box of its triangles, a node child's
/// box the union of its children's boxes), and the per-octant child orders (wide_order.h), which
/// rank the children by their box centres. A fresh build chooses its splits for the new positions;
/// a refit keeps the old ones, so its boxes may overlap more: wide_sah_cost() measures by how much.
/// Lauterbach et al., "RT-DEFORM: Interactive Ray Tracing of Dynamic Scenes using BVHs", 2006,
/// measure the same loss and rebuild when it grows.
#include "accel/wide/wide_layout.h"

namespace arbor::accel {

/// Rewrites the leaves' vertices from `tris` (the view the layout was made over, with new
/// positions: the same indices, every triangle of the layout finite) and recomputes every box and
/// the child orders. Parallel over the nodes for the leaves, then one pass from the last node to the
/// root for the node children: the result does not depend on the thread count (box unions are
/// exact). Returns wide_sah_cost() of the refitted layout.
template <std::size_t N> double refit_wide_layout(WideLayout<N>& layout, const TriangleView& tris);

/// The layout's SAH cost normalized to its root box's area: the sum over nodes of the area of the
/// node's box (one node test each) plus, over leaf children, the area of the leaf's box times its
/// blocks (one block test each), divided by the root box's area. 0 for an empty layout or a root
/// box of zero area. Summed in a fixed order (deterministic).
template <std::size_t N> double wide_sah_cost(const WideLayout<N>& layout);

extern template double refit_wide_layout<4>(WideLayout<4>&, const TriangleView&);
extern template double refit_wide_layout<8>(WideLayout<8>&, const TriangleView&);
extern template double refit_wide_layout<16>(WideLayout<16>&, const TriangleView&);
extern template double wide_sah_cost<4>(const WideLayout<4>&);
extern template double wide_sah_cost<8>(const WideLayout<8>&);
extern template double wide_sah_cost<16>(const WideLayout<16>&);

}  // namespace arbor::accel
