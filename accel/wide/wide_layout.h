#pragma once
/// WideLayout<N>: the traversal layout of the SIMD paths, collapsed on purpose from any BinaryBvh
/// (bvh-median, bvh-sah, lbvh) into N-wide nodes (N = 4, 8 or 16).
///
/// A node holds the boxes of up to N children in SoA form (simd::BoxesSoA<N>), so one SIMD slab
/// test reads all of them; unused slots hold empty boxes (lo = +inf, hi = -inf) that never hit.
/// Leaves are runs of whole SoA triangle blocks of the same width (simd::TrisSoA<N>) holding the
/// ORIGINAL vertices (the watertight test needs bit-identical inputs for shared edges); unused lanes
/// hold NaN vertices, which never hit. Nodes are stored depth-first (pre-order).
///
/// The collapse is SAH-optimal for the given binary tree (dynamic programming over the slots each
/// binary subtree may take, Ylitie et al., HPG 2017; see Collapser::plan): it chooses which binary
/// nodes become wide nodes, which are skipped (their children pulled up into the parent's slots) and
/// which subtrees of at most `merge_triangles` triangles become one leaf, pricing a node test and a
/// leaf by its blocks. The child boxes are the binary boxes, so the collapse keeps the tree's bounds
/// exactly. See also "Shallow Bounding Volume Hierarchies for Fast SIMD Ray Tracing of Incoherent
/// Rays", H. Dammertz et al., EGSR 2008, and Wald et al., "Getting Rid of Packets", RT 2008.
#include "accel/bvh/binary_bvh.h"
#include "accel/util/uninit_vector.h"
#include "accel/wide/wide_config.h"
#include "simd/box_kernels.h"
#include "simd/tri_kernels.h"

#include <cstdint>
#include <vector>

namespace arbor::accel {

/// One N-wide node: child boxes in SoA, and per child either an interior node (count == 0: node
/// index in child) or a leaf (count > 0 triangles in blocks child, child + 1, ...). Slots
/// >= `children` are empty boxes.
template <std::size_t N> struct alignas(64) WideNode {
    simd::BoxesSoA<N> boxes;
    std::uint32_t child[N];
    std::uint16_t count[N];
    std::uint8_t children;

    bool is_leaf(std::size_t c) const { return count[c] != 0; }
};
static_assert(sizeof(WideNode<4>) == 128 && sizeof(WideNode<8>) == 256 && sizeof(WideNode<16>) == 512);

/// Blocks of a leaf of `count` triangles.
template <std::size_t N> constexpr std::uint32_t wide_blocks(std::uint32_t count) {
    return (count + std::uint32_t(N) - 1) / std::uint32_t(N);
}

/// A leaf block: N triangles in SoA form and their original numbers right behind them (an id is
/// read only for a hit, and then from a line next to the ones the test just read: kept in a
/// separate array, that read was a cache miss of its own, a quarter of the leaf time on
/// incoherent rays). Unused lanes: NaN vertices, id invalid_prim.
template <std::size_t N> struct WideBlock {
    simd::TrisSoA<N> tris;
    std::uint32_t ids[N];

    const float* soa() const { return &tris.v[0][0][0]; }
};

template <std::size_t N> struct WideLayout {
    static constexpr std::size_t width = N;
    UninitVector<WideNode<N>> nodes;     ///< nodes[0] is the root (always a node); none when empty
    UninitVector<WideBlock<N>> blocks;   ///< triangle blocks in leaf order
    /// A layout made with WideLeaves::ids: per slot of the blocks there would be (block * N + lane)
    /// its triangle (invalid_prim: padding), and no blocks.
    UninitVector<std::uint32_t> ids;
    /// Per node and ray octant, the order of its children for the single-ray walk (wide_order.h):
    /// orders[(node * 8 + octant) * N + j], j = 0 the farthest.
    UninitVector<std::uint8_t> orders;
    std::uint32_t depth = 0;               ///< node levels on the deepest path (root = 1)
    std::size_t leaves = 0;

    bool empty() const { return nodes.empty(); }
    /// Entries a traversal stack may need: every node on a path pushes at most N - 1 (the single-ray
    /// walk pushes N, the nearest popped at once; its vector push writes N entries at the top).
    std::size_t stack_size() const { return std::size_t(depth) * (N - 1) + 1 + N; }
    std::size_t memory_bytes() const {
        return nodes.capacity() * sizeof(WideNode<N>) + blocks.capacity() * sizeof(WideBlock<N>) + orders.capacity() +
               ids.capacity() * sizeof(std::uint32_t) + sizeof(WideLayout);
    }
    /// Blocks of triangle slots (those of an ids-only layout included).
    std::size_t block_count() const { return blocks.empty() ? ids.size() / N : blocks.size(); }
    /// Vertex k of triangle slot s (block s / N, lane s % N), and its original number.
    Vec3f vertex(std::size_t slot, int k) const {
        const auto& b = blocks[slot / N].tris;
        const std::size_t l = slot % N;
        return {b.v[k][0][l], b.v[k][1][l], b.v[k][2][l]};
    }
    std::uint32_t prim(std::size_t slot) const { return blocks.empty() ? ids[slot] : blocks[slot / N].ids[slot % N]; }
};

/// What a wide layout's leaves hold: blocks of their triangles' vertices (a layout to trace), or
/// only their triangles' numbers (WideLayout::ids: the compact layout's source, compact_layout.h,
/// which reads its vertices from the mesh; such a layout cannot be traced, and keeps the compact
/// build's peak near the compact layout's own size).
enum class WideLeaves : std::uint8_t { blocks, ids };

/// Collapses `bvh` (built over `tris`) into N-wide nodes. Deterministic: the node structure is
/// laid out serially, leaves are filled in parallel at offsets fixed beforehand.
template <std::size_t N>
WideLayout<N> make_wide_layout(const BinaryBvh& bvh, const TriangleView& tris, const WideConfig& cfg = {},
                               WideLeaves leaves = WideLeaves::blocks);

extern template WideLayout<4> make_wide_layout<4>(const BinaryBvh&, const TriangleView&, const WideConfig&, WideLeaves);
extern template WideLayout<8> make_wide_layout<8>(const BinaryBvh&, const TriangleView&, const WideConfig&, WideLeaves);
extern template WideLayout<16> make_wide_layout<16>(const BinaryBvh&, const TriangleView&, const WideConfig&, WideLeaves);

}  // namespace arbor::accel
