#include "accel/wide/compact_layout.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>
#include <utility>
#include <vector>

#include "accel/wide/compact_quantize.h"

namespace arbor::accel {

template <std::size_t N>
CompactLayout<N> make_compact_layout(WideLayout<N>&& wide, const TriangleView& tris) {
    CompactLayout<N> out;
    out.depth = wide.depth;
    out.leaves = wide.leaves;
    if (wide.empty()) return out;
    // Each leaf's first triangle in the packed array: leaves by first block (their blocks are
    // whole and disjoint), then a running sum of their counts.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> leaves;  // (first block, count)
    leaves.reserve(wide.leaves);
    for (const WideNode<N>& n : wide.nodes)
        for (std::size_t c = 0; c < n.children; ++c)
            if (n.count[c] != 0) leaves.emplace_back(n.child[c], n.count[c]);
    std::sort(leaves.begin(), leaves.end());
    std::vector<std::uint32_t> start(wide.blocks.size() + 1, 0);
    std::size_t total = 0;
    for (const auto& [first, count] : leaves) {
        start[first] = std::uint32_t(total);
        total += count;
    }
    out.refs.resize(4 * total + N);
    std::fill(out.refs.end() - N, out.refs.end(), 0u);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 4096),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i != r.end(); ++i) {
                              const auto [first, count] = leaves[i];
                              std::uint32_t* leaf = out.refs.data() + 4 * std::size_t(start[first]);
                              for (std::uint32_t s = 0; s < count; ++s) {
                                  const std::uint32_t prim = wide.prim(std::size_t(first) * N + s);
                                  for (std::size_t k = 0; k < 3; ++k)
                                      leaf[k * count + s] = tris.indices[3 * std::size_t(prim) + k];
                                  leaf[3 * std::size_t(count) + s] = prim;
                              }
                          }
                      });
    // The vertices in the order the leaves first use them (one serial pass: the numbering must
    // not depend on the thread count).
    {
        std::vector<std::uint32_t> renumber(tris.vertex_count(), ~0u);
        std::uint32_t next = 0;
        for (const auto& [first, count] : leaves) {
            std::uint32_t* leaf = out.refs.data() + 4 * std::size_t(start[first]);
            for (std::uint32_t s = 0; s < count; ++s)  // (triangle by triangle: first use order)
                for (std::size_t k = 0; k < 3; ++k) {
                    std::uint32_t& v = leaf[k * count + s];
                    if (renumber[v] == ~0u) renumber[v] = next++;
                    v = renumber[v];
                }
        }
        out.verts.resize(3 * std::size_t(next));
        for (std::size_t i = 0; i < renumber.size(); ++i)
            if (renumber[i] != ~0u) {
                float* p = out.verts.data() + 3 * std::size_t(renumber[i]);
                p[0] = tris.x[i], p[1] = tris.y[i], p[2] = tris.z[i];
            }
    }
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

template CompactLayout<4> make_compact_layout<4>(WideLayout<4>&&, const TriangleView&);
template CompactLayout<8> make_compact_layout<8>(WideLayout<8>&&, const TriangleView&);
template CompactLayout<16> make_compact_layout<16>(WideLayout<16>&&, const TriangleView&);

}  // namespace arbor::accel
