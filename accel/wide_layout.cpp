#include "accel/wide_layout.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace arbor::accel {

namespace {

/// A child of a wide node under construction: the triangles [offset, offset + count) of binary
/// node `bin`'s subtree (in depth-first leaf order), and whether it is a whole subtree that may be
/// opened further.
struct Kid {
    std::uint32_t bin;
    std::uint32_t offset, count;
    bool whole;
};

/// A leaf to fill: its triangles and its first block.
struct LeafJob {
    std::uint32_t bin, offset, count, first_block;
};

template <std::size_t N> class Collapser {
public:
    Collapser(const BinaryBvh& bvh, const TriangleView& tris, const WideConfig& cfg, WideLayout<N>& out)
        : bvh_(bvh), tris_(tris), out_(out) {
        merge_ = cfg.merge_triangles ? cfg.merge_triangles : std::uint32_t(N);
        max_leaf_ = std::clamp<std::uint32_t>(cfg.max_leaf_triangles, 1, 65535);
        const std::size_t n = bvh.nodes.size();
        sub_tris_.assign(n, 0);
        for (std::size_t i = n; i-- > 0;) {  // children come after their parents
            const BvhBuildNode& node = bvh.nodes[i];
            sub_tris_[i] = node.is_leaf() ? node.count : sub_tris_[node.first] + sub_tris_[node.first + 1];
        }
    }

    void run() {
        if (bvh_.nodes.empty() || sub_tris_[0] == 0) return;
        std::vector<Kid> kids;
        if (leaf_like(0)) kids.push_back({0, 0, sub_tris_[0], true});
        else kids = open(0);
        build_node(kids, 1);
        out_.blocks.resize(next_block_);
        out_.leaves = jobs_.size();
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, jobs_.size(), 64), [&](const tbb::blocked_range<std::size_t>& r) {
            std::vector<std::uint32_t> prims;
            for (std::size_t j = r.begin(); j != r.end(); ++j) fill_leaf(jobs_[j], prims);
        });
    }

private:
    bool leaf_like(std::uint32_t bin) const { return bvh_.nodes[bin].is_leaf() || sub_tris_[bin] <= merge_; }

    /// The children of interior binary node `bin` after greedy opening: largest area first.
    std::vector<Kid> open(std::uint32_t bin) const {
        const BvhBuildNode& node = bvh_.nodes[bin];
        std::vector<Kid> kids{{node.first, 0, sub_tris_[node.first], true},
                              {node.first + 1, 0, sub_tris_[node.first + 1], true}};
        while (kids.size() < N) {
            std::size_t best = kids.size();
            double best_area = -1.0;
            for (std::size_t k = 0; k < kids.size(); ++k) {
                if (leaf_like(kids[k].bin)) continue;
                const double a = bvh_.nodes[kids[k].bin].box.area();
                if (a > best_area) best_area = a, best = k;  // first of equals: deterministic
            }
            if (best == kids.size()) break;
            const BvhBuildNode& b = bvh_.nodes[kids[best].bin];
            kids[best] = {b.first, 0, sub_tris_[b.first], true};
            kids.insert(kids.begin() + std::ptrdiff_t(best) + 1, Kid{b.first + 1, 0, sub_tris_[b.first + 1], true});
        }
        return kids;
    }

    /// Kids for a leaf too big for one wide leaf: up to N chunks of about equal size.
    std::vector<Kid> chunk(const Kid& k) const {
        const std::uint32_t pieces = std::min<std::uint32_t>(std::uint32_t(N), (k.count + max_leaf_ - 1) / max_leaf_);
        std::vector<Kid> kids;
        for (std::uint32_t p = 0; p < pieces; ++p) {
            const std::uint32_t b = std::uint32_t(std::uint64_t(k.count) * p / pieces);
            const std::uint32_t e = std::uint32_t(std::uint64_t(k.count) * (p + 1) / pieces);
            kids.push_back({k.bin, k.offset + b, e - b, false});
        }
        return kids;
    }

    /// Appends a node for `kids` (and, depth first, its descendants); returns its index.
    std::uint32_t build_node(const std::vector<Kid>& kids, std::uint32_t depth) {
        const auto index = std::uint32_t(out_.nodes.size());
        out_.nodes.emplace_back();
        out_.depth = std::max(out_.depth, depth);
        {
            WideNode<N>& n = out_.nodes[index];
            for (std::size_t c = 0; c < N; ++c) {
                n.boxes.set_empty(c);
                n.child[c] = 0;
                n.count[c] = 0;
            }
            n.children = std::uint8_t(kids.size());
        }
        for (std::size_t c = 0; c < kids.size(); ++c) {
            const Kid& k = kids[c];
            std::uint32_t child = 0, count = 0;
            if (k.whole && !leaf_like(k.bin)) {
                child = build_node(open(k.bin), depth + 1);
            } else if (k.count > max_leaf_) {
                child = build_node(chunk(k), depth + 1);
            } else {
                child = next_block_;
                count = k.count;
                jobs_.push_back({k.bin, k.offset, k.count, next_block_});
                next_block_ += wide_blocks<N>(k.count);
            }
            WideNode<N>& n = out_.nodes[index];  // (the vector may have grown)
            const Bounds& box = bvh_.nodes[k.bin].box;
            n.boxes.set(c, box.lo, box.hi);
            n.child[c] = child;
            n.count[c] = std::uint16_t(count);
        }
        return index;
    }

    /// Triangles of binary node `bin`'s subtree in depth-first leaf order.
    void gather(std::uint32_t bin, std::vector<std::uint32_t>& prims) const {
        const BvhBuildNode& node = bvh_.nodes[bin];
        if (node.is_leaf()) {
            prims.insert(prims.end(), bvh_.prim_ids.begin() + node.first, bvh_.prim_ids.begin() + node.first + node.count);
            return;
        }
        gather(node.first, prims);
        gather(node.first + 1, prims);
    }

    void fill_leaf(const LeafJob& job, std::vector<std::uint32_t>& prims) {
        // A binary leaf's triangles are one range of prim_ids; a merged subtree is gathered.
        const BvhBuildNode& node = bvh_.nodes[job.bin];
        const std::uint32_t* src = bvh_.prim_ids.data() + node.first;
        if (!node.is_leaf()) {
            prims.clear();
            gather(job.bin, prims);
            src = prims.data();
        }
        for (std::uint32_t b = 0; b < wide_blocks<N>(job.count); ++b) {
            WideBlock<N>& block = out_.blocks[job.first_block + b];
            for (std::uint32_t l = 0; l < N; ++l) {
                const std::uint32_t i = b * std::uint32_t(N) + l;
                if (i >= job.count) {
                    block.tris.set_empty(l);
                    block.ids[l] = invalid_prim;
                    continue;
                }
                const std::uint32_t tri = src[job.offset + i];
                block.tris.set(l, tris_.corner(tri, 0), tris_.corner(tri, 1), tris_.corner(tri, 2));
                block.ids[l] = tri;
            }
        }
    }

    const BinaryBvh& bvh_;
    const TriangleView& tris_;
    WideLayout<N>& out_;
    std::uint32_t merge_ = N, max_leaf_ = 65535;
    std::vector<std::uint32_t> sub_tris_;
    std::vector<LeafJob> jobs_;
    std::uint32_t next_block_ = 0;
};

}  // namespace

template <std::size_t N> WideLayout<N> make_wide_layout(const BinaryBvh& bvh, const TriangleView& tris, const WideConfig& cfg) {
    WideLayout<N> out;
    Collapser<N>(bvh, tris, cfg, out).run();
    return out;
}

template WideLayout<4> make_wide_layout<4>(const BinaryBvh&, const TriangleView&, const WideConfig&);
template WideLayout<8> make_wide_layout<8>(const BinaryBvh&, const TriangleView&, const WideConfig&);
template WideLayout<16> make_wide_layout<16>(const BinaryBvh&, const TriangleView&, const WideConfig&);

}  // namespace arbor::accel
