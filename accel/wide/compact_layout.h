#pragma once
/// CompactLayout<N>: the compact mode's traversal layout (BuildConfig::compact, `--compact`), made
/// from the N-wide layout (wide_layout.h) of the same tree and then kept instead of it, for about
/// half the bytes per triangle.
///
/// A node holds its children's boxes quantized to 8 bits per plane relative to the node's own
/// frame (compact_quantize.h: an origin and a power-of-two scale per axis; decoded, each box
/// contains the true one), the child references and counts as WideNode does: 128 bytes for 8
/// children, 256 for 16 (WideNode: 256 and 512). A leaf of n triangles is ceil(n / N) blocks of
/// up to N triangles, back to back in `refs` (CompactBlock below): per block its triangles'
/// numbers, per triangle three one-byte corner numbers, and the block's own copy of the ORIGINAL
/// float vertices its triangles use, each once (by axis, in first-use order): a
/// block's vertices lie beside its other words, so the walk's prefetch of a leaf brings them too
/// and a leaf test is one chain of loads, not an index load and then vertex gathers elsewhere.
/// The walk reads those very floats (permuted or gathered), so the watertight test sees bit for
/// bit the inputs it sees on the other layouts. The octant orders of the N-wide layout are kept as they are.
#include <bit>
#include <cstdint>

#include "accel/core/geometry.h"
#include "accel/util/uninit_vector.h"
#include "accel/wide/wide_layout.h"

namespace arbor::accel {

/// One node: per axis the frame (origin, scale: compact_quantize.h) and the children's planes as
/// steps q[0] (lo) and q[1] (hi), per axis and child; per child either a node (count == 0: node
/// index in child) or a leaf (count > 0 triangles whose first block starts at CompactLayout::refs[child]).
/// Slots >= `children` are never taken (the walk masks them out).
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

/// One block of a compact leaf, `nb` triangles (1 .. N) whose words start at `w`:
///   w[0]                   m, the number of the block's own vertices (<= 3 nb)
///   w[1 .. 1 + nb)         the triangles' numbers, ascending
///   3 nb bytes             the corners: byte k nb + s is the block's number of vertex k of
///                          triangle s (padded to whole words)
///   3 m floats             the block's vertices by axis: x of vertex i at i, y at m + i, z at 2m + i
///                          (so that one axis of up to 32 vertices fits two registers of 16 lanes,
///                          which a permute reads instead of a gather: compact_traverse.h)
struct CompactBlock {
    const std::uint32_t* w;
    std::uint32_t nb;

    static constexpr std::size_t words(std::uint32_t nb, std::uint32_t m) {
        return 1 + std::size_t(nb) + (3 * std::size_t(nb) + 3) / 4 + 3 * std::size_t(m);
    }
    std::uint32_t prim(std::uint32_t s) const { return w[1 + s]; }
    const std::uint8_t* corners() const { return reinterpret_cast<const std::uint8_t*>(w + 1 + nb); }
    std::uint32_t vertex_count() const { return w[0]; }
    /// Axis a of the block's vertices (vertex_count() floats).
    const float* axis(int a) const { return reinterpret_cast<const float*>(w + words(nb, 0) + std::size_t(a) * w[0]); }
    Vec3f vertex(std::uint32_t s, int k) const {
        const std::uint32_t* v = w + (words(nb, 0) + std::size_t(corners()[std::size_t(k) * nb + s]));
        return {std::bit_cast<float>(v[0]), std::bit_cast<float>(v[w[0]]),
                std::bit_cast<float>(v[2 * std::size_t(w[0])])};
    }
    /// The next block of the leaf, holding `nb_next` triangles.
    CompactBlock next(std::uint32_t nb_next) const { return {w + words(nb, w[0]), nb_next}; }
};

template <std::size_t N>
struct CompactLayout {
    static constexpr std::size_t width = N;
    UninitVector<CompactNode<N>> nodes;  ///< nodes[0] is the root; none when empty
    /// The leaves' blocks (CompactBlock) in leaf order (each leaf in ascending prim order), and 8
    /// zero words of padding at the end (the walk's loads of a block's corners may read past it).
    UninitVector<std::uint32_t> refs;
    UninitVector<std::uint8_t> orders;  ///< as WideLayout::orders
    std::uint32_t depth = 0;
    std::size_t leaves = 0;

    bool empty() const { return nodes.empty(); }
    std::size_t stack_size() const { return std::size_t(depth) * (N - 1) + 1 + N; }
    /// The layout's arrays, its vertices included.
    std::size_t memory_bytes() const {
        return nodes.capacity() * sizeof(CompactNode<N>) + refs.capacity() * sizeof(std::uint32_t) + orders.capacity() +
               sizeof(CompactLayout);
    }
    /// The first block of the leaf (first, n).
    CompactBlock block(std::uint32_t first, std::uint32_t n) const {
        return {refs.data() + first, n < N ? n : std::uint32_t(N)};
    }
    /// Calls f(block, b) for each block of the leaf (first, n), b its first triangle's place in the leaf.
    template <class F>
    void for_blocks(std::uint32_t first, std::uint32_t n, F&& f) const {
        CompactBlock blk = block(first, n);
        for (std::uint32_t b = 0;;) {
            f(blk, b);
            b += blk.nb;
            if (b >= n) return;
            blk = blk.next(n - b < N ? n - b : std::uint32_t(N));
        }
    }
};

/// The compact layout of `wide` (built over `tris`): its nodes quantized, its leaves as blocks
/// with their own copies of their vertices. `wide` is consumed (its orders are moved). With
/// max_bytes (0: no limit), the layout and the lists that place its leaves must fit in it: their
/// sizes are worked out first, and MemoryLimitError is thrown before the layout is allocated.
/// *scratch_bytes (when given) gets those lists' bytes, for the build's peak.
template <std::size_t N>
CompactLayout<N> make_compact_layout(WideLayout<N>&& wide, const TriangleView& tris, std::uint64_t max_bytes = 0,
                                     std::size_t* scratch_bytes = nullptr);

extern template CompactLayout<4> make_compact_layout<4>(WideLayout<4>&&, const TriangleView&,
                                                            std::uint64_t, std::size_t*);
extern template CompactLayout<8> make_compact_layout<8>(WideLayout<8>&&, const TriangleView&,
                                                            std::uint64_t, std::size_t*);
extern template CompactLayout<16> make_compact_layout<16>(WideLayout<16>&&, const TriangleView&,
                                                            std::uint64_t, std::size_t*);

}  // namespace arbor::accel
