#pragma once
/// The kd-tree's traversal layout: 8-byte nodes in depth-first order, one record per leaf with its
/// box and six ropes (Popov, Günther, Seidel, Slusallek 2007, "Stackless KD-Tree Traversal for High
/// Performance GPU Ray Tracing"), and the triangles each leaf references.
#include "accel/core/geometry.h"

#include <cstdint>
#include <vector>

namespace arbor::accel {

/// A rope that leads nowhere: the face lies on the scene box.
inline constexpr std::uint32_t kd_no_rope = 0xFFFFFFFFu;
/// Largest depth any kd-tree may have (the builder clamps its depth limit to this); traversal
/// stacks of this size never overflow.
inline constexpr std::uint32_t kd_max_depth = 60;

/// 8 bytes. Interior node: split plane `split` on axis() (0, 1, 2); the left child (the half below
/// the plane) is the next node in the array, the right child is nodes[index()]. Leaf: axis() == 3
/// and index() numbers its KdLeaf.
struct KdNode {
    float split = 0.0f;
    std::uint32_t bits = 3u;  ///< low 2 bits: axis, or 3 for a leaf; upper 30 bits: index

    bool is_leaf() const { return (bits & 3u) == 3u; }
    int axis() const { return int(bits & 3u); }
    std::uint32_t index() const { return bits >> 2; }

    static KdNode interior(int axis, float split, std::uint32_t right_child) {
        return {split, (right_child << 2) | std::uint32_t(axis)};
    }
    static KdNode leaf(std::uint32_t leaf_index) { return {0.0f, (leaf_index << 2) | 3u}; }
};
static_assert(sizeof(KdNode) == 8);
/// Node and leaf indices must fit in the 30 index bits.
inline constexpr std::uint32_t kd_max_index = (1u << 30) - 1u;

/// Face numbering of the ropes: 2 * axis for the min face, 2 * axis + 1 for the max face.
inline constexpr int kd_face(int axis, bool max_side) { return 2 * axis + (max_side ? 1 : 0); }

/// 56 bytes. The leaf's box, its ropes (node index of the smallest node that contains the whole
/// face on the other side, or kd_no_rope on the scene box) and its triangles refs[first, first + count).
struct KdLeaf {
    Bounds box;
    std::uint32_t rope[6] = {kd_no_rope, kd_no_rope, kd_no_rope, kd_no_rope, kd_no_rope, kd_no_rope};
    std::uint32_t first = 0;
    std::uint32_t count = 0;
};
static_assert(sizeof(KdLeaf) == 56);

/// One triangle as the traversal reads it (40 bytes): corners and its number in the input view.
struct KdTriangle {
    Vec3f v0, v1, v2;
    std::uint32_t prim = 0;
};
static_assert(sizeof(KdTriangle) == 40);

/// A built kd-tree. Triangles are stored once (`tris`, in the order of their first reference by a
/// leaf); a leaf's refs index into them. Empty when the input has no finite triangle.
struct KdTree {
    std::vector<KdNode> nodes;         ///< nodes[0] is the root; a single leaf for tiny scenes
    std::vector<KdLeaf> leaves;        ///< in depth-first order
    std::vector<std::uint32_t> refs;   ///< per leaf, indices into tris, ascending prim order
    std::vector<KdTriangle> tris;      ///< the finite triangles, each once
    Bounds box;                        ///< scene box: bounds of the finite triangles
    std::uint32_t depth_limit = 0;     ///< the limit the builder used
    std::size_t dropped_nonfinite = 0; ///< triangles left out because a corner is NaN/Inf
    std::size_t build_peak_bytes = 0;  ///< largest temporary memory of the build

    bool empty() const { return tris.empty(); }
    /// Bytes of the traversal structure: nodes, leaves, refs and triangles.
    std::size_t memory_bytes() const {
        return nodes.size() * sizeof(KdNode) + leaves.size() * sizeof(KdLeaf) + refs.size() * sizeof(std::uint32_t) +
               tris.size() * sizeof(KdTriangle);
    }
};

}  // namespace arbor::accel
