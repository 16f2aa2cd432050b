#pragma once
/// The hierarchy of an LBVH: a binary radix tree over sorted Morton codes, collapsed into leaves of
/// at most max_leaf_size primitives and written in the canonical BinaryBvh layout.
///
/// Keys are augmented with their sorted position, so duplicate codes are told apart: the prefix
/// length of positions i and j is clz(code_i ^ code_j) when the codes differ, and 128 +
/// clz32(i ^ j) when they are equal (64 + clz of the fine codes in between, in marked runs). A run of equal codes therefore splits on the position bits
/// (at a power-of-two boundary near the middle), which bounds the depth by 64 + log2(n) and never
/// makes a leaf larger than max_leaf_size. Internal nodes are named as in Karras 2012: node 0 is
/// the root, and an internal node's children are its split position gamma (left) and gamma + 1
/// (right). Both methods below build the same tree, so their outputs are bit-identical.
#include "accel/bvh/binary_bvh.h"
#include "accel/bvh/build_prims.h"

#include <cstdint>
#include <span>
#include <vector>

namespace arbor::accel {

/// How the radix tree is found.
enum class RadixTreeMethod {
    /// Karras 2012, "Maximizing Parallelism in the Construction of BVHs, Octrees, and k-d Trees":
    /// every internal node independently (tbb::parallel_for), then bounds bottom-up with one atomic
    /// visit counter per node (the counters order the work; they decide no placement).
    karras,
    /// Recursive split at the first differing bit (binary search), tbb::parallel_invoke above the
    /// parallel threshold; stops descending at subtrees of at most max_leaf_size primitives.
    top_down,
};

struct RadixTreeInput {
    /// Sorted keys; the Morton code of position i is keys[i] >> code_shift (the low bits may hold
    /// payload, e.g. the primitive index under a 30-bit code).
    std::span<const std::uint64_t> keys;
    int code_shift = 0;
    /// The reference (index into prims) at each sorted position; when empty, the low 32 bits of
    /// keys[i] hold it.
    std::span<const std::uint32_t> sorted_refs;
    /// Optional finer codes per reference (indexed by the reference, not the position). Requires
    /// the references in the keys (sorted_refs empty) and code_shift 32; bit 62 of a key then marks
    /// a run of equal codes that is sorted by (fine code, position): there the fine codes decide
    /// before the position. Unmarked runs are ordered by position only.
    std::span<const std::uint64_t> fine_codes;
    /// Boxes and triangle ids of the references (read once per primitive, at the leaves: one
    /// 32-byte record each).
    std::span<const BuildPrim> prims;
    std::uint32_t max_leaf_size = 4;        ///< collapse subtrees of at most this many primitives (>= 1)
    std::uint32_t parallel_threshold = 1024; ///< subtrees smaller than this run serially
    /// false: every subtree of at most max_leaf_size primitives becomes a leaf. true: only when the
    /// SAH says so (leaf cost area * n * intersection_cost <= the subtree's cost, where an internal
    /// node costs area * traversal_cost); larger subtrees are always split.
    bool sah_collapse = false;
    float traversal_cost = 1.0f, intersection_cost = 1.0f;
};

struct RadixTreeResult {
    /// Canonical layout: depth-first, siblings adjacent, children after parents. Leaf ranges are
    /// sorted positions (first, count); they tile [0, n) in order.
    std::vector<BvhBuildNode> nodes;
    /// Triangle id of each sorted position (BinaryBvh::prim_ids).
    std::vector<std::uint32_t> prim_ids;
    std::size_t temp_bytes = 0;  ///< temporary memory used on top of the inputs and the output
};

/// Builds the collapsed tree over keys.size() primitives (empty input: no nodes; one primitive:
/// one leaf). Requires prims (one per reference), and sorted_refs empty or of keys.size() (std::invalid_argument).
/// Deterministic: the result depends only on the input.
RadixTreeResult build_radix_tree(const RadixTreeInput& in, RadixTreeMethod method);

}  // namespace arbor::accel
