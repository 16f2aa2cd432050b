#pragma once
/// Refit of the scalar two-box layout (bvh2_layout.h): the triangles it was made over, at new
/// positions. The nodes, leaves and triangle slots stay; the slots' vertex copies are rewritten and
/// every box is recomputed bottom-up (a leaf child's box from its triangles, a node child's box as
/// the union of that node's two child boxes). The wide layout's counterpart is wide/wide_refit.h.
#include "accel/bvh/bvh2_layout.h"

namespace arbor::accel {

/// Rewrites every slot's vertices from `tris` (the view the layout was made over, with new
/// positions: the same indices, every triangle of the layout finite) and recomputes every box and
/// root_box. Parallel over the nodes for the leaves, then one backward pass for the node children:
/// the result does not depend on the thread count. Returns bvh2_sah_cost() of the refitted layout.
double refit_bvh2_layout(Bvh2Layout& layout, const TriangleView& tris);

/// The layout's SAH cost normalized to root_box's area: the sum over nodes of their box's area
/// plus, over leaves, their box's area times their triangles, divided by the root box's area (0 for
/// an empty layout or a root box of zero area). Summed in a fixed order.
double bvh2_sah_cost(const Bvh2Layout& layout);

}  // namespace arbor::accel
