#pragma once
/// The order in which the single-ray walk visits a wide node's hit children: fixed per node and ray
/// octant when the layout is made, instead of sorted by entry distance at every visit.
///
/// For each node and each of the 8 octants of a ray direction (the signs of d.x, d.y, d.z) the
/// node's children are ranked by how far along that octant's diagonal their box centres lie; a ray
/// of that octant pushes its hit children in that order, far to near, so the nearest one ends up on
/// top of the stack. The walk then needs no comparisons and no data-dependent branches to order
/// children (each was a mispredicted branch, ~4 per incoherent ray), and on AVX-512 the push is one
/// permute and one compress per field (wide_push.h). The order is an approximation of the exact
/// entry-distance order; a closest hit is still exact (a farther child is only visited before a
/// nearer one, never skipped), and the distances pushed with the children still cull them once a
/// closer hit is found. Ylitie, Karras and Laine, "Efficient Incoherent Ray Traversal on GPUs
/// Through Compressed Wide BVHs", HPG 2017, order children by ray octant the same way.
#include "accel/wide/wide_layout.h"

#include <cstdint>

namespace arbor::accel {

/// Octant of a ray direction from its sign bits (near_is_hi[k] = 1 when d[k] has its sign bit set).
inline int ray_octant(const int near_is_hi[3]) { return near_is_hi[0] | near_is_hi[1] << 1 | near_is_hi[2] << 2; }

/// Fills layout.orders: for node i and octant o, the N lanes at orders[(i * 8 + o) * N] are a
/// permutation of 0..N-1, far to near along the octant's diagonal d = (+-1, +-1, +-1) (the
/// child's key is d . (lo + hi)); unused slots come first, ties keep the lower lane nearer.
/// Deterministic (each node on its own, in parallel).
template <std::size_t N> void make_octant_orders(WideLayout<N>& layout);

extern template void make_octant_orders<4>(WideLayout<4>&);
extern template void make_octant_orders<8>(WideLayout<8>&);
extern template void make_octant_orders<16>(WideLayout<16>&);

}  // namespace arbor::accel
