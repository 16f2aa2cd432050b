#include "accel/wide/wide_layout.h"
#include "accel/wide/wide_order.h"

#include "accel/core/memory_limit.h"
#include "accel/util/prefault.h"
#include "accel/util/scratch_array.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_scan.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>

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

/// At most N kids of one wide node (no heap allocation per node).
template <std::size_t N> struct Kids {
    std::array<Kid, N> kid;
    std::uint32_t size = 0;
    void push_back(const Kid& k) { kid[size++] = k; }
};

/// Subtrees with more triangles than this are planned as two parallel tasks.
constexpr std::uint32_t parallel_plan_tris = 4096;

template <std::size_t N> class Collapser {
public:
    Collapser(const BinaryBvh& bvh, const TriangleView& tris, const WideConfig& cfg, WideLeaves leaves,
              WideLayout<N>& out)
        : bvh_(bvh), tris_(tris), out_(out) {
        merge_ = cfg.merge_triangles ? cfg.merge_triangles : std::uint32_t(N);
        max_leaf_ = std::clamp<std::uint32_t>(cfg.max_leaf_triangles, 1, 65535);
        node_cost_ = cfg.node_cost;
        block_cost_ = cfg.block_cost;
        ids_only_ = leaves == WideLeaves::ids;
        max_bytes_ = cfg.max_bytes;
        const std::size_t n = bvh.nodes.size();
        resize_prefaulted(sub_tris_, n);  // (written in parallel: mapped first, on huge pages where big)
        resize_prefaulted(slots_, n);
        if (n != 0) count(0);
        // Row i of the cost and choice tables holds slots 1..slots_[i] (a subtree cannot fill more
        // slots than it has binary leaves): rows back to back, most of them far shorter than N.
        resize_prefaulted(row_, n + 1);
        const std::size_t total = tbb::parallel_scan(
            tbb::blocked_range<std::size_t>(0, n, 65536), std::size_t(0),
            [&](const tbb::blocked_range<std::size_t>& r, std::size_t at, bool final) {
                for (std::size_t i = r.begin(); i != r.end(); ++i) {
                    if (final) row_[i] = at;
                    at += slots_[i];
                }
                return at;
            },
            std::plus<>());
        row_[n] = total;
    }

    void run() {
        if (bvh_.nodes.empty() || sub_tris_[0] == 0) return;
        cost_ = ScratchArray<float>(row_.back());
        choice_ = ScratchArray<std::uint8_t>(row_.back());
        leaf_ = ScratchArray<std::uint8_t>(bvh_.nodes.size());
        plan(0);
        Kids<N> kids;
        if (leaf_[0]) kids.push_back({0, 0, sub_tris_[0], true});
        else collect(0, std::uint32_t(N), kids);
        // A dry run first, so that the node and job arrays are allocated once at their size (no
        // regrowth copies; no page fault per 4 KiB in the serial walk below).
        std::size_t nodes = 0, leaves = 0, blocks = 0;
        tally(kids, nodes, leaves, blocks);
        // The layout's arrays (WideLayout::memory_bytes: nodes, octant orders, blocks or ids), known
        // from the plan before any is allocated.
        const std::uint64_t block_bytes = ids_only_ ? N * sizeof(std::uint32_t) : sizeof(WideBlock<N>);
        const std::uint64_t bytes = std::uint64_t(nodes) * (sizeof(WideNode<N>) + 8 * N) +
                                    std::uint64_t(blocks) * block_bytes + sizeof(WideLayout<N>);
        if (max_bytes_ != 0 && bytes > max_bytes_)
            throw MemoryLimitError("its " + std::to_string(N) + "-wide SIMD layout needs " + mib_text(bytes) +
                                   ", more than the " + mib_text(max_bytes_) + " left");
        resize_prefaulted(out_.nodes, nodes);
        resize_prefaulted(jobs_, leaves);
        build_node(kids, 1);
        if (next_node_ != nodes || next_job_ != leaves || next_block_ != blocks)
            throw std::logic_error("wide layout: the dry run and the build disagree");
        if (ids_only_)
            resize_prefaulted(out_.ids, std::size_t(next_block_) * N);
        else
            resize_prefaulted(out_.blocks, next_block_);
        out_.leaves = jobs_.size();
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, jobs_.size(), 64), [&](const tbb::blocked_range<std::size_t>& r) {
            std::vector<std::uint32_t> prims;
            for (std::size_t j = r.begin(); j != r.end(); ++j) fill_leaf(jobs_[j], prims);
        });
    }

private:
    /// Cost of binary node n's subtree over at most k slots (1 <= k <= slots_[n]), and the split.
    float& cost(std::uint32_t n, std::uint32_t k) { return cost_[row_[n] + k - 1]; }
    std::uint8_t choice(std::uint32_t n, std::uint32_t k) const { return choice_[row_[n] + k - 1]; }

    /// Triangles and slots (min(N, binary leaves)) of binary node i's subtree, children first;
    /// the top levels of a big tree as parallel tasks (each writes only its own entries).
    void count(std::uint32_t i, std::uint32_t depth = 0) {
        const BvhBuildNode& node = bvh_.nodes[i];
        if (node.is_leaf()) {
            sub_tris_[i] = node.count, slots_[i] = 1;
            return;
        }
        const std::uint32_t lc = node.first, rc = node.first + 1;
        if (depth < 12 && bvh_.nodes.size() > 2 * std::size_t(parallel_plan_tris))
            tbb::parallel_invoke([&] { count(lc, depth + 1); }, [&] { count(rc, depth + 1); });
        else
            count(lc, depth + 1), count(rc, depth + 1);
        sub_tris_[i] = sub_tris_[lc] + sub_tris_[rc];
        slots_[i] = std::uint8_t(std::min<std::uint32_t>(std::uint32_t(N), slots_[lc] + slots_[rc]));
    }

    /// The SAH-optimal collapse of binary node i's subtree by dynamic programming, bottom-up (Ylitie
    /// et al., "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", HPG 2017):
    /// cost(n, k) is the least SAH cost of n's subtree spread over at most k slots of a wide node;
    /// one slot is n itself, as a leaf (area x blocks x block cost, allowed up to merge_
    /// triangles; a binary leaf always) or as a wide node (area x node cost + its subtree spread
    /// over N slots). choice(n, k) records how many of the k slots go to the left child (0: fewer
    /// slots suffice). Slots beyond a subtree's leaf count change nothing, so the tables stop
    /// there. Children are planned before their parent, big subtrees as parallel tasks (each
    /// writes only its own rows: the same tables for any thread count).
    void plan(std::uint32_t i) {
        const BvhBuildNode& node = bvh_.nodes[i];
        const double area = std::max(0.0, double(node.box.area()));
        const double as_leaf = area * block_cost_ * double(wide_blocks<N>(sub_tris_[i]));
        if (node.is_leaf()) {
            leaf_[i] = 1;
            cost(i, 1) = float(as_leaf);
            choice_[row_[i]] = 0;
            return;
        }
        const std::uint32_t lc = node.first, rc = node.first + 1;
        if (sub_tris_[i] > parallel_plan_tris) tbb::parallel_invoke([&] { plan(lc); }, [&] { plan(rc); });
        else plan(lc), plan(rc);
        const std::uint32_t nl = slots_[lc], nr = slots_[rc], ni = slots_[i];
        const float* l = &cost_[row_[lc]] - 1;  // l[a]: a = 1..nl
        const float* r = &cost_[row_[rc]] - 1;
        float* c = &cost_[row_[i]] - 1;
        std::uint8_t* ch = &choice_[row_[i]] - 1;
        for (std::uint32_t k = 2; k <= ni; ++k) {  // the two children over k slots
            float best = INFINITY;
            std::uint8_t split = 1;
            const std::uint32_t a_lo = k > nr ? k - nr : 1, a_hi = std::min(k - 1, nl);
            for (std::uint32_t a = a_lo; a <= a_hi; ++a) {
                const float v = l[a] + r[k - a];
                if (v < best) best = v, split = std::uint8_t(a);  // first of equals: deterministic
            }
            c[k] = best;
            ch[k] = split;
        }
        // A wide node spreads the subtree over all N slots; ni of them are all it can fill.
        const double as_node = area * node_cost_ + double(c[ni]);
        const bool leaf = sub_tris_[i] <= merge_ && as_leaf <= as_node;
        leaf_[i] = leaf ? 1 : 0;
        c[1] = float(leaf ? as_leaf : as_node);
        ch[1] = 0;
        for (std::uint32_t k = 2; k <= ni; ++k)
            if (c[k - 1] < c[k]) c[k] = c[k - 1], ch[k] = 0;
    }

    /// Appends the kids of binary node `bin` spread over at most `slots` slots, as planned.
    void collect(std::uint32_t bin, std::uint32_t slots, Kids<N>& kids) const {
        const BvhBuildNode& node = bvh_.nodes[bin];
        slots = std::min<std::uint32_t>(slots, slots_[bin]);
        while (slots > 1 && !node.is_leaf() && choice(bin, slots) == 0) --slots;
        if (slots <= 1 || node.is_leaf()) {
            kids.push_back({bin, 0, sub_tris_[bin], true});
            return;
        }
        const std::uint32_t a = choice(bin, slots);
        collect(node.first, a, kids);
        collect(node.first + 1, slots - a, kids);
    }

    /// Kids for a leaf too big for one wide leaf: up to N chunks of about equal size.
    Kids<N> chunk(const Kid& k) const {
        const std::uint32_t pieces = std::min<std::uint32_t>(std::uint32_t(N), (k.count + max_leaf_ - 1) / max_leaf_);
        Kids<N> kids;
        for (std::uint32_t p = 0; p < pieces; ++p) {
            const std::uint32_t b = std::uint32_t(std::uint64_t(k.count) * p / pieces);
            const std::uint32_t e = std::uint32_t(std::uint64_t(k.count) * (p + 1) / pieces);
            kids.push_back({k.bin, k.offset + b, e - b, false});
        }
        return kids;
    }

    /// The nodes, leaves and blocks build_node(kids) writes: the same walk, nothing written.
    void tally(const Kids<N>& kids, std::size_t& nodes, std::size_t& leaves, std::size_t& blocks) const {
        ++nodes;
        for (std::size_t c = 0; c < kids.size; ++c) {
            const Kid& k = kids.kid[c];
            if (k.whole && !leaf_[k.bin]) {
                Kids<N> sub;
                collect(k.bin, std::uint32_t(N), sub);
                tally(sub, nodes, leaves, blocks);
            } else if (k.count > max_leaf_) {
                tally(chunk(k), nodes, leaves, blocks);
            } else {
                ++leaves;
                blocks += wide_blocks<N>(k.count);
            }
        }
    }

    /// Writes the next node for `kids` (and, depth first, its descendants); returns its index.
    std::uint32_t build_node(const Kids<N>& kids, std::uint32_t depth) {
        const auto index = std::uint32_t(next_node_++);
        out_.depth = std::max(out_.depth, depth);
        {
            WideNode<N>& n = out_.nodes[index];
            // Zero children, counts and padding (the same bytes for any thread count), empty boxes.
            std::memset(static_cast<void*>(&n), 0, sizeof n);
            for (std::size_t c = 0; c < N; ++c) n.boxes.set_empty(c);
            n.children = std::uint8_t(kids.size);
        }
        for (std::size_t c = 0; c < kids.size; ++c) {
            const Kid& k = kids.kid[c];
            std::uint32_t child = 0, count = 0;
            if (k.whole && !leaf_[k.bin]) {
                Kids<N> sub;
                collect(k.bin, std::uint32_t(N), sub);
                child = build_node(sub, depth + 1);
            } else if (k.count > max_leaf_) {
                child = build_node(chunk(k), depth + 1);
            } else {
                child = next_block_;
                count = k.count;
                jobs_[next_job_++] = {k.bin, k.offset, k.count, next_block_};
                next_block_ += wide_blocks<N>(k.count);
            }
            WideNode<N>& n = out_.nodes[index];
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
        prims.clear();
        if (node.is_leaf()) prims.insert(prims.end(), bvh_.prim_ids.begin() + node.first, bvh_.prim_ids.begin() + node.first + node.count);
        else gather(job.bin, prims);
        // The leaf's triangles in ascending prim order, so that the lowest of the lanes of a block
        // tied at the smallest t is the lowest prim (the tie rule, core/hit_record.h).
        // A triangle listed twice (a subtree of the kd-tree's cells, kdtree_cells.h, merged into
        // one leaf: a triangle crossing a plane is in both cells) is kept once; the lanes it frees
        // at the end are padding. (A BVH lists each triangle once: nothing changes.)
        const auto begin = prims.begin() + job.offset;
        std::sort(begin, begin + job.count);
        const auto unique = std::uint32_t(std::unique(begin, begin + job.count) - begin);
        const std::uint32_t* src = prims.data();
        if (ids_only_) {
            std::uint32_t* out = out_.ids.data() + std::size_t(job.first_block) * N;
            for (std::uint32_t i = 0; i < wide_blocks<N>(job.count) * std::uint32_t(N); ++i)
                out[i] = i < unique ? src[job.offset + i] : invalid_prim;
            return;
        }
        for (std::uint32_t b = 0; b < wide_blocks<N>(job.count); ++b) {
            WideBlock<N>& block = out_.blocks[job.first_block + b];
            for (std::uint32_t l = 0; l < N; ++l) {
                const std::uint32_t i = b * std::uint32_t(N) + l;
                if (i >= unique) {
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
    double node_cost_ = 1.0, block_cost_ = 1.0;
    bool ids_only_ = false;
    std::uint64_t max_bytes_ = 0;
    UninitVector<std::uint32_t> sub_tris_;  ///< every entry written by count() before it is read
    UninitVector<std::uint8_t> slots_;      ///< min(N, binary leaves in the subtree)
    UninitVector<std::size_t> row_;         ///< first entry of each node's row in cost_ / choice_
    ScratchArray<float> cost_;
    ScratchArray<std::uint8_t> choice_, leaf_;
    UninitVector<LeafJob> jobs_;  ///< sized by the dry run, every entry written by build_node
    std::size_t next_node_ = 0, next_job_ = 0;
    std::uint32_t next_block_ = 0;
};

}  // namespace

template <std::size_t N>
WideLayout<N> make_wide_layout(const BinaryBvh& bvh, const TriangleView& tris, const WideConfig& cfg, WideLeaves leaves) {
    WideLayout<N> out;
    Collapser<N>(bvh, tris, cfg, leaves, out).run();
    make_octant_orders(out);
    return out;
}

template WideLayout<4> make_wide_layout<4>(const BinaryBvh&, const TriangleView&, const WideConfig&, WideLeaves);
template WideLayout<8> make_wide_layout<8>(const BinaryBvh&, const TriangleView&, const WideConfig&, WideLeaves);
template WideLayout<16> make_wide_layout<16>(const BinaryBvh&, const TriangleView&, const WideConfig&, WideLeaves);

}  // namespace arbor::accel
