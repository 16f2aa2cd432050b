#pragma once
/// The kd-tree's triangles in SIMD blocks for the SIMD paths: each leaf's triangles (in the leaf's
/// ascending prim order) copied into SoA blocks of N (simd::TrisSoA<N>), the last one padded with
/// NaN vertices, which never hit. A triangle referenced by several leaves is copied into each.
#include "accel/kdtree/kdtree_node.h"
#include "simd/tri_kernels.h"

#include <cstdint>
#include <vector>

namespace arbor::accel {

/// N triangles of one leaf and their numbers in the input view (padding: invalid_prim).
template <std::size_t N> struct KdBlock {
    simd::TrisSoA<N> tris;
    std::uint32_t ids[N];
};

template <std::size_t N> struct KdBlocks {
    std::vector<std::uint32_t> first;  ///< leaves + 1 entries: leaf l owns blocks [first[l], first[l + 1])
    std::vector<KdBlock<N>> blocks;

    std::size_t memory_bytes() const {
        return first.size() * sizeof(std::uint32_t) + blocks.size() * sizeof(KdBlock<N>);
    }
};

/// The blocks of every leaf of `tree` (empty tree: no blocks, first = {0}).
template <std::size_t N> KdBlocks<N> make_kd_blocks(const KdTree& tree) {
    KdBlocks<N> out;
    out.first.resize(tree.leaves.size() + 1);
    std::size_t total = 0;
    for (std::size_t l = 0; l < tree.leaves.size(); ++l) {
        out.first[l] = std::uint32_t(total);
        total += (tree.leaves[l].count + N - 1) / N;
    }
    out.first[tree.leaves.size()] = std::uint32_t(total);
    out.blocks.resize(total);
    for (std::size_t l = 0; l < tree.leaves.size(); ++l) {
        const KdLeaf& leaf = tree.leaves[l];
        const std::uint32_t slots = (out.first[l + 1] - out.first[l]) * std::uint32_t(N);
        for (std::uint32_t i = 0; i < slots; ++i) {
            KdBlock<N>& b = out.blocks[out.first[l] + i / N];
            if (i < leaf.count) {
                const KdTriangle& t = tree.tris[tree.refs[leaf.first + i]];
                b.tris.set(i % N, t.v0, t.v1, t.v2);
                b.ids[i % N] = t.prim;
            } else {
                b.tris.set_empty(i % N);
                b.ids[i % N] = invalid_prim;
            }
        }
    }
    return out;
}

}  // namespace arbor::accel
