#pragma once
/// CompactLayout<N>: the compact mode's traversal layout (BuildConfig::compact, `--compact`), made
/// from the N-wide layout (wide_layout.h) of the same tree and then kept instead of it, for about
/// half the bytes per triangle.
///
/// A node holds its children's boxes quantized to 8 bits per plane relative to the node's own
/// frame (compact_quantize.h: an origin and a power-of-two scale per axis; decoded, each box
/// contains the true one), the child references and counts as WideNode does: 128 bytes for 8
/// children, 256 for 16 (WideNode: 256 and 512). A leaf of n triangles is 4n words of `refs`: the
/// first vertex index of each, then the second, the third, then their numbers, 16 bytes a triangle
/// with no padding (WideBlock: 40 bytes a triangle slot, its unused slots included); the walk loads
/// N indices at once. The vertices are the layout's own copy of the
/// mesh's, interleaved (x, y, z) and in the order the leaves first use them, 12 bytes each: a
/// leaf's vertices then share a few cache lines (from the mesh's own three arrays, in the mesh's
/// order, each vertex cost up to three lines of its own). Each vertex is shared by the triangles
/// that share it, as in the mesh. The walk gathers these
/// ORIGINAL float vertices, so the watertight test sees bit for bit the inputs it sees on the
/// other layouts. The octant orders of the N-wide layout are kept as they are.
#include <cstdint>

#include "accel/core/geometry.h"
#include "accel/util/uninit_vector.h"
#include "accel/wide/wide_layout.h"

namespace arbor::accel {

/// One node: per axis the frame (origin, scale: compact_quantize.h) and the children's planes as
/// steps q[0] (lo) and q[1] (hi), per axis and child; per child either a node (count == 0: node
/// index in child) or a leaf (count > 0 triangles whose words start at CompactLayout::refs[4 * child]). Slots >=
/// `children` are never taken (the walk masks them out).
template <std::size_t N>
struct alignas(64) CompactNode {
    float origin[3];
    float scale[3];
    std::uint8_t q[2][3][N];
    std::uint32_t child[N];
    std::uint16_t count[N];
    std::uint8_t children;

    bool is_leaf(std::size_t c) const { return count[c] != 0; }
};
static_assert(sizeof(CompactNode<4>) == 128 && sizeof(CompactNode<8>) == 128 && sizeof(CompactNode<16>) == 256);

template <std::size_t N>
struct CompactLayout {
    static constexpr std::size_t width = N;
    UninitVector<CompactNode<N>> nodes;  ///< nodes[0] is the root; none when empty
    /// The leaves in leaf order (each in ascending prim order), 4 words a triangle as above, and N
    /// words of padding at the end (the walk's loads may read past a leaf's words).
    UninitVector<std::uint32_t> refs;
    UninitVector<std::uint8_t> orders;  ///< as WideLayout::orders
    /// The vertices the leaves use, x, y, z of vertex i at 3i, 3i + 1, 3i + 2 (first use order).
    UninitVector<float> verts;
    std::uint32_t depth = 0;
    std::size_t leaves = 0;

    bool empty() const { return nodes.empty(); }
    std::size_t stack_size() const { return std::size_t(depth) * (N - 1) + 1 + N; }
    /// The layout's arrays, its vertices included.
    std::size_t memory_bytes() const {
        return nodes.capacity() * sizeof(CompactNode<N>) + refs.capacity() * sizeof(std::uint32_t) + orders.capacity() +
               verts.capacity() * sizeof(float) + sizeof(CompactLayout);
    }
    /// Vertex k of triangle s of the leaf (first, n), and its number.
    Vec3f vertex(std::uint32_t first, std::uint32_t n, std::uint32_t s, int k) const {
        const float* v = verts.data() + 3 * std::size_t(refs[4 * std::size_t(first) + std::size_t(k) * n + s]);
        return {v[0], v[1], v[2]};
    }
    std::uint32_t prim(std::uint32_t first, std::uint32_t n, std::uint32_t s) const {
        return refs[4 * std::size_t(first) + 3 * std::size_t(n) + s];
    }
};

/// The compact layout of `wide` (built over `tris`): its nodes quantized, its leaves as indices
/// into its own copy of the vertices they use. `wide` is consumed (its orders are moved).
template <std::size_t N>
CompactLayout<N> make_compact_layout(WideLayout<N>&& wide, const TriangleView& tris);

extern template CompactLayout<4> make_compact_layout<4>(WideLayout<4>&&, const TriangleView&);
extern template CompactLayout<8> make_compact_layout<8>(WideLayout<8>&&, const TriangleView&);
extern template CompactLayout<16> make_compact_layout<16>(WideLayout<16>&&, const TriangleView&);

}  // namespace arbor::accel
