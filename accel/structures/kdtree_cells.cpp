// The kd-tree's cells as a binary BVH and the kd-tree with the cell paths (kdtree_cells.h).
#include "accel/structures/kdtree_cells.h"

#include "accel/util/timer.h"

#include <algorithm>
#include <stdexcept>

namespace arbor::accel {

namespace {

/// Pre-order conversion of the kd-tree: `full[n]` says whether kd node n's subtree holds a
/// non-empty leaf; a node with one full child is skipped down to that child (its cell the box).
class CellConverter {
public:
    CellConverter(const KdTree& tree, bool tight, BinaryBvh& out)
        : tree_(tree), out_(out), full_(tree.nodes.size(), 0), tight_(tight) {}

    void run() {
        if (tree_.nodes.empty() || !mark(0)) return;
        out_.nodes.emplace_back();
        place(0, tree_.box, 0);
    }

private:
    /// Marks which subtrees hold triangles (children first); returns node n's mark.
    bool mark(std::uint32_t n) {
        const KdNode& node = tree_.nodes[n];
        bool full = false;
        if (node.is_leaf()) full = tree_.leaves[node.index()].count != 0;
        else full = mark(n + 1) | mark(node.index());  // (both marked: `|`, not `||`)
        full_[n] = full ? 1 : 0;
        return full;
    }

    /// Writes full kd node n (cell `cell`) into out_.nodes[slot], its descendants after it.
    void place(std::uint32_t n, Bounds cell, std::uint32_t slot) {
        for (;;) {
            const KdNode& node = tree_.nodes[n];
            if (node.is_leaf()) {
                const KdLeaf& leaf = tree_.leaves[node.index()];
                BvhBuildNode& b = out_.nodes[slot];
                b.first = std::uint32_t(out_.prim_ids.size());
                b.count = leaf.count;
                Bounds tris;
                for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
                    const KdTriangle& t = tree_.tris[tree_.refs[i]];
                    out_.prim_ids.push_back(t.prim);
                    tris.grow(t.v0), tris.grow(t.v1), tris.grow(t.v2);
                }
                // Tight: the cell cut to its triangles' bounds (still holds every point of a
                // triangle inside the cell).
                b.box = cell;
                if (tight_) b.box.lo = simd::vmax(cell.lo, tris.lo), b.box.hi = simd::vmin(cell.hi, tris.hi);
                return;
            }
            const int axis = node.axis();
            Bounds below = cell, above = cell;
            below.hi[axis] = node.split;
            above.lo[axis] = node.split;
            const std::uint32_t lc = n + 1, rc = node.index();
            if (full_[lc] && full_[rc]) {
                const auto first = std::uint32_t(out_.nodes.size());
                out_.nodes.emplace_back();
                out_.nodes.emplace_back();
                place(lc, below, first);
                place(rc, above, first + 1);
                BvhBuildNode& b = out_.nodes[slot];
                b.box = cell;
                if (tight_) {
                    b.box = out_.nodes[first].box;
                    b.box.grow(out_.nodes[first + 1].box);
                }
                b.first = first;
                b.count = 0;
                return;
            }
            // One full child: it takes this node's place, with its own (smaller) cell.
            if (full_[lc]) n = lc, cell = below;
            else n = rc, cell = above;
        }
    }

    const KdTree& tree_;
    BinaryBvh& out_;
    std::vector<std::uint8_t> full_;
    bool tight_;
};

}  // namespace

BinaryBvh kd_cell_bvh(const KdTree& tree, bool tight) {
    BinaryBvh out;
    out.dropped_nonfinite = tree.dropped_nonfinite;
    CellConverter(tree, tight, out).run();
    return out;
}

KdPrimView kd_prim_view(const KdTree& tree) {
    KdPrimView v;
    std::uint32_t prims = 0;
    for (const KdTriangle& t : tree.tris) prims = std::max(prims, t.prim + 1);
    v.x.resize(3 * tree.tris.size());
    v.y.resize(3 * tree.tris.size());
    v.z.resize(3 * tree.tris.size());
    v.indices.assign(3 * std::size_t(prims), 0u);
    for (std::size_t i = 0; i < tree.tris.size(); ++i) {
        const KdTriangle& t = tree.tris[i];
        const Vec3f c[3] = {t.v0, t.v1, t.v2};
        for (int k = 0; k < 3; ++k) {
            v.x[3 * i + k] = c[k].x, v.y[3 * i + k] = c[k].y, v.z[3 * i + k] = c[k].z;
            v.indices[3 * std::size_t(t.prim) + k] = std::uint32_t(3 * i + k);
        }
    }
    return v;
}

namespace {

/// The kd-tree with the cell layout for its SIMD paths: the cell tree's wide BVH (an Accel of its
/// own, built with the SIMD layout only), to which `single` and `packet` go. The scalar path and
/// the counted mode stay the rope walk.
class KdCellAccel final : public KdTreeAccel {
public:
    KdCellAccel(KdTree&& tree, const BuildConfig& cfg, double build_ms, const KdCellPaths& paths)
        : KdTreeAccel(std::move(tree), cfg, build_ms), walk_(cfg.kd_blocks.walk) {
        const Timer timer;
        std::size_t temp_bytes = 0;
        {
            const BinaryBvh cells = kd_cell_bvh(tree_, cfg.kd_blocks.walk == KdWalk::tight_cells);
            const KdPrimView prims = kd_prim_view(tree_);
            temp_bytes = cells.nodes.capacity() * sizeof(BvhBuildNode) + cells.prim_ids.capacity() * sizeof(std::uint32_t) +
                         (prims.x.capacity() * 3 + prims.indices.capacity()) * sizeof(float);
            BuildConfig wide_cfg = cfg;
            wide_cfg.layouts = Layouts::simd;
            wide_cfg.compact = false;  // (compact mode is the BVHs'; its leaves would read `prims`' arrays)
            cells_ = paths.make(cells, prims.view(), wide_cfg);
        }
        stats_.build_ms += timer.ms();
        const BuildStats& cs = cells_->stats();
        cell_bytes_ = cs.memory_bytes;
        stats_.memory_bytes += cell_bytes_;
        stats_.build_peak_bytes = std::max(stats_.build_peak_bytes, tree_.memory_bytes() + temp_bytes + cs.build_peak_bytes);
        offer_.add(TracePath::single);
        offer_.add(TracePath::packet);
        offer_.simd_skipped = false;
        offer_.packet_lanes = cells_->offer().packet_lanes;
        offer_.packets_pay = cells_->offer().packets_pay;
        offer_.scene_diagonal = cells_->offer().scene_diagonal;
        block_width_ = paths.width;
    }

    KdWalk walk() const override { return walk_; }
    const Accel* cell_paths() const override { return cells_.get(); }

private:
    void run(std::span<const Ray> rays, std::span<Hit> hits, Query query, TracePath path,
             TraceCounters* counters) const override {
        if (counters || path == TracePath::scalar) return run_scalar(rays, hits, query, counters);
        cells_->trace(rays, hits, {query, path});
    }

    KdWalk walk_;
    std::unique_ptr<Accel> cells_;
    std::size_t cell_bytes_ = 0;
};

}  // namespace

std::unique_ptr<KdTreeAccel> make_kd_cell_accel(KdTree tree, const BuildConfig& cfg, double build_ms,
                                                const KdCellPaths& paths) {
    return std::make_unique<KdCellAccel>(std::move(tree), cfg, build_ms, paths);
}

}  // namespace arbor::accel
