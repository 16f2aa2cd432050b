#include "accel/wide/compact_layout.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <utility>
#include <vector>

#include "accel/core/memory_limit.h"
#include "accel/wide/compact_quantize.h"

namespace arbor::accel {

template <std::size_t N>
CompactLayout<N> make_compact_layout(WideLayout<N>&& wide, const TriangleView& tris, std::uint64_t max_bytes,
                                     std::size_t* scratch_bytes) {
    CompactLayout<N> out;
    out.depth = wide.depth;
    out.leaves = wide.leaves;
    if (wide.empty()) return out;
    // The leaves by first block (their blocks are whole and disjoint). A block's vertices (global
    // numbers, first use order) and its corners as numbers into them are worked out twice, in
    // parallel: first for the leaves' sizes, whose running sum places them, then to write them
    // (cheaper than keeping them: at most 3N vertices a block, found by a short search).
    std::vector<std::pair<std::uint32_t, std::uint32_t>> leaves;  // (first block, count)
    leaves.reserve(wide.leaves);
    for (const WideNode<N>& n : wide.nodes)
        for (std::size_t c = 0; c < n.children; ++c)
            if (n.count[c] != 0) leaves.emplace_back(n.child[c], n.count[c]);
    std::sort(leaves.begin(), leaves.end());
    // Block `block`'s nb triangles: its vertices into v (global numbers), its corners into
    // corners[k * nb + s]; returns their count.
    const auto block_vertices = [&](std::size_t block, std::uint32_t nb, std::uint32_t* v, std::uint8_t* corners) {
        std::uint32_t m = 0;
        for (std::uint32_t s = 0; s < nb; ++s) {  // (triangle by triangle: first use order)
            const std::uint32_t prim = wide.prim(block * N + s);
            for (std::size_t k = 0; k < 3; ++k) {
                const std::uint32_t g = tris.indices[3 * std::size_t(prim) + k];
                std::uint32_t at = 0;
                while (at < m && v[at] != g) ++at;
                if (at == m) v[m++] = g;
                corners[k * nb + s] = std::uint8_t(at);
            }
        }
        return m;
    };
    std::vector<std::size_t> leaf_words(leaves.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          std::uint32_t v[3 * N];
                          std::uint8_t corners[3 * N];
                          for (std::size_t i = r.begin(); i != r.end(); ++i) {
                              const auto [first, count] = leaves[i];
                              std::size_t words = 0;
                              for (std::uint32_t b = 0; b < count; b += N) {
                                  const std::uint32_t nb = std::min<std::uint32_t>(count - b, N);
                                  words += CompactBlock::words(nb, block_vertices(first + b / N, nb, v, corners));
                              }
                              leaf_words[i] = words;
                          }
                      });
    std::vector<std::uint32_t> start(wide.block_count() + 1, 0);  // by first block: the leaf's first word
    std::size_t total = 0;
    for (std::size_t i = 0; i < leaves.size(); ++i) {
        if (total > 0xffffffffu) throw std::length_error("compact layout: more than 2^32 words of leaves");
        start[leaves[i].first] = std::uint32_t(total);
        total += leaf_words[i];
    }
    // Known now, before the layout's arrays are allocated: its nodes and words (the orders are the
    // wide layout's, moved), and the lists above beside them.
    const std::uint64_t layout_bytes = std::uint64_t(wide.nodes.size()) * sizeof(CompactNode<N>) +
                                       (std::uint64_t(total) + 8) * sizeof(std::uint32_t) + sizeof(CompactLayout<N>);
    const std::size_t scratch = leaves.capacity() * sizeof(leaves[0]) + leaf_words.capacity() * sizeof(std::size_t) +
                                start.capacity() * sizeof(std::uint32_t);
    if (scratch_bytes) *scratch_bytes = scratch;
    if (max_bytes != 0 && layout_bytes + scratch > max_bytes)
        throw MemoryLimitError("its " + std::to_string(N) + "-wide compact layout needs " + mib_text(layout_bytes + scratch) +
                               ", more than the " + mib_text(max_bytes) + " left");
    out.refs.resize(total + 8);
    std::fill(out.refs.end() - 8, out.refs.end(), 0u);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, leaves.size(), 1024), [&](const tbb::blocked_range<std::size_t>& r) {
            std::uint32_t v[3 * N];
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                const auto [first, count] = leaves[i];
                std::uint32_t* w = out.refs.data() + start[first];
                for (std::uint32_t b = 0; b < count; b += N) {
                    const std::size_t block = std::size_t(first) + b / N;
                    const std::uint32_t nb = std::min<std::uint32_t>(count - b, N);
                    const std::size_t corner_words = (3 * std::size_t(nb) + 3) / 4;
                    std::fill(w + 1 + nb, w + 1 + nb + corner_words, 0u);
                    const std::uint32_t m = block_vertices(block, nb, v, reinterpret_cast<std::uint8_t*>(w + 1 + nb));
                    w[0] = m;
                    for (std::uint32_t s = 0; s < nb; ++s) w[1 + s] = wide.prim(block * N + s);
                    std::uint32_t* x = w + 1 + nb + corner_words;
                    for (std::uint32_t j = 0; j < m; ++j) {
                        x[j] = std::bit_cast<std::uint32_t>(tris.x[v[j]]);
                        x[m + j] = std::bit_cast<std::uint32_t>(tris.y[v[j]]);
                        x[2 * m + j] = std::bit_cast<std::uint32_t>(tris.z[v[j]]);
                    }
                    w += CompactBlock::words(nb, m);
                }
            }
        });
    out.nodes.resize(wide.nodes.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, wide.nodes.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i != r.end(); ++i) {
                              const WideNode<N>& w = wide.nodes[i];
                              CompactNode<N>& n = out.nodes[i];
                              n.children = w.children;
                              for (int k = 0; k < 3; ++k) {
                                  float lo = INFINITY, hi = -INFINITY;
                                  for (std::size_t c = 0; c < w.children; ++c) {
                                      lo = std::min(lo, w.boxes.b[0][k][c]);
                                      hi = std::max(hi, w.boxes.b[1][k][c]);
                                  }
                                  const CompactAxis a = CompactAxis::fit(lo, hi);
                                  n.origin[k] = a.origin;
                                  n.scale[k] = a.scale;
                                  for (std::size_t c = 0; c < N; ++c) {
                                      const bool used = c < w.children;
                                      // (Unused slots: an inverted box; the walk masks them out anyway.)
                                      n.q[0][k][c] = used ? a.quantize_lo(w.boxes.b[0][k][c]) : 255;
                                      n.q[1][k][c] = used ? a.quantize_hi(w.boxes.b[1][k][c]) : 0;
                                  }
                              }
                              for (std::size_t c = 0; c < N; ++c) {
                                  const bool leaf = c < w.children && w.count[c] != 0;
                                  n.child[c] = leaf ? start[w.child[c]] : w.child[c];
                                  n.count[c] = w.count[c];
                              }
                          }
                      });
    out.orders = std::move(wide.orders);
    wide = WideLayout<N>{};
    return out;
}

template CompactLayout<4> make_compact_layout<4>(WideLayout<4>&&, const TriangleView&, std::uint64_t,
                                                     std::size_t*);
template CompactLayout<8> make_compact_layout<8>(WideLayout<8>&&, const TriangleView&, std::uint64_t,
                                                     std::size_t*);
template CompactLayout<16> make_compact_layout<16>(WideLayout<16>&&, const TriangleView&, std::uint64_t,
                                                     std::size_t*);

}  // namespace arbor::accel
