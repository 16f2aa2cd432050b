#pragma once
/// Bvh2Layout: the traversal layout of a binary BVH, converted on purpose from a BinaryBvh.
///
/// Nodes are flattened depth-first (the first child of an interior node, when interior, is the next
/// node) and one 64-byte node holds the boxes of BOTH children in SoA form, so a traversal step
/// reads one cache line and tests two boxes. Triangles are permuted into leaf order and stored as
/// SoA blocks of 4 with the ORIGINAL vertices (not edges): the watertight test needs bit-identical
/// vertex inputs for triangles that share an edge. Leaves are packed back to back (a leaf may
/// start inside a block): padding every leaf to whole blocks doubled the triangle memory and made
/// the conversion of a 2.5M-triangle scene 2x slower, for no gain in the scalar traversal. The wide
/// layouts of the SIMD issue are collapsed from the same BinaryBvh (they do not start from this one).
#include "accel/bvh/binary_bvh.h"
#include "accel/util/uninit_vector.h"

#include <cstdint>
#include <vector>

namespace arbor::accel {

/// Triangles per SoA block (one SSE-width test reads a block).
inline constexpr std::uint32_t tri_block_width = 4;

/// 64 bytes, one cache line. Per axis, x[] = {lo of child 0, lo of child 1, hi of child 0, hi of
/// child 1}: a ray with a negative direction component reads its near planes at index 2 + c, a ray
/// with a positive one at index c. count[c] == 0: child c is the interior node nodes[child[c]];
/// count[c] > 0: child c is a leaf of triangle slots [child[c], child[c] + count[c]) (slot s lives
/// in block s / 4, lane s % 4).
struct alignas(64) Bvh2Node {
    float x[4], y[4], z[4];
    std::uint32_t child[2];
    std::uint32_t count[2];

    bool is_leaf(int c) const { return count[c] != 0; }
};
static_assert(sizeof(Bvh2Node) == 64);

/// Four triangle slots, SoA: v0[axis][lane], v1[axis][lane], v2[axis][lane]. Lanes past the last
/// triangle of the scene repeat it (a 4-wide test may read the whole last block).
struct alignas(16) TriBlock4 {
    float v0[3][4], v1[3][4], v2[3][4];
};
static_assert(sizeof(TriBlock4) == 144);

struct Bvh2Layout {
    UninitVector<Bvh2Node> nodes;          ///< interior nodes, depth-first; nodes[0] is the root when interior
    UninitVector<TriBlock4> blocks;        ///< triangles in leaf order
    UninitVector<std::uint32_t> prim_ids;  ///< per slot (4 per block): the original triangle number
    Bounds root_box;                      ///< box of the root (empty for an empty scene)
    std::uint32_t root_child = 0;         ///< root as a child reference: node 0, or a leaf when
    std::uint32_t root_count = 0;         ///< root_count > 0 (a tiny scene whose root is a leaf)
    std::uint32_t max_depth = 0;          ///< deepest leaf; a traversal stack needs max_depth + 1 entries

    bool empty() const { return root_box.empty(); }
    /// Exact bytes of the arrays a traversal reads (capacity, not size).
    std::size_t memory_bytes() const {
        return nodes.capacity() * sizeof(Bvh2Node) + blocks.capacity() * sizeof(TriBlock4) +
               prim_ids.capacity() * sizeof(std::uint32_t) + sizeof(Bvh2Layout);
    }
    /// Triangle slot s: vertices and original id.
    Vec3f vertex(std::uint32_t slot, int k) const {
        const TriBlock4& b = blocks[slot / tri_block_width];
        const std::uint32_t l = slot % tri_block_width;
        const auto& v = k == 0 ? b.v0 : (k == 1 ? b.v1 : b.v2);
        return {v[0][l], v[1][l], v[2][l]};
    }
};

/// Converts `bvh` (built over `tris`) to the traversal layout. Parallel above a subtree size, and
/// deterministic: node and block offsets come from subtree sizes, not from scheduling.
Bvh2Layout make_bvh2_layout(const BinaryBvh& bvh, const TriangleView& tris);

/// The memory_bytes() of make_bvh2_layout(bvh, ...), from the tree alone, before it is made.
std::size_t bvh2_layout_bytes(const BinaryBvh& bvh);

}  // namespace arbor::accel
