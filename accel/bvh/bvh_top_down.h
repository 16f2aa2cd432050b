#pragma once
/// The recursive top-down frame shared by the bvh-median, bvh-sah and full-sweep builders. A builder
/// only supplies a splitter that decides, for a range of build primitives, "leaf" or where to cut
/// (after partitioning the range in place). The frame recurses with tbb::parallel_invoke above
/// cfg.parallel_threshold and stays deterministic: ranges below the threshold are built into their
/// own node arrays, and one final pass places all of them at offsets computed from subtree sizes,
/// so node order never depends on scheduling.
#include "accel/bvh/binary_bvh.h"
#include "accel/bvh/bvh_build_config.h"
#include "accel/bvh/build_prims.h"
#include "accel/util/prefault.h"
#include "accel/util/uninit_vector.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <atomic>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace arbor::accel::detail {

/// The build primitives (build_prims.h), partitioned in place by the builders.
using accel::BuildPrim;

/// A range [begin, end) of the build primitives with its box and centroid box.
struct BuildTask {
    std::uint32_t begin = 0, end = 0, depth = 0;
    Bounds box, cbox;
    std::uint32_t size() const { return end - begin; }
};

/// Where a range was cut: [begin, mid) and [mid, end), both non-empty, with their bounds.
struct SplitResult {
    std::uint32_t mid = 0;
    Bounds left_box, left_cbox, right_box, right_cbox;
};

/// Boxes and centroid boxes of [begin, mid) and [mid, end).
SplitResult bounds_of_halves(std::span<const BuildPrim> prims, std::uint32_t begin, std::uint32_t mid, std::uint32_t end);
/// Splits at the middle index without reordering (all centroids equal: no order helps).
SplitResult index_median_split(std::span<BuildPrim> prims, const BuildTask& t);
/// Object median along `axis` (std::nth_element on the centroids); deterministic for a given input.
SplitResult object_median_split(std::span<BuildPrim> prims, const BuildTask& t, int axis);
/// Axis of the largest centroid-box extent, or -1 when every extent is zero.
int longest_axis(const Bounds& cbox);

/// Where the subtrees keep their nodes: one array with room for any binary tree over n primitives
/// (2n - 1 nodes), reserved but not mapped up front: advised to use huge pages, it is mapped only
/// where pieces are handed out (a few faults of 2 MiB, where a vector per chunk faulted each 4 KiB
/// page of the workers' heaps: 4.4M triangles, 6k faults). A chunk, built in a scratch vector, is
/// copied into the next free piece (an atomic counter: where it lands depends on the schedule,
/// what assemble() writes from it does not).
class NodeStore {
public:
    /// What a build's peak counts, checked as nodes are kept: `fixed` bytes from the start, then
    /// `per_node` bytes a node and `per_keep` bytes a keep() call; past `limit` (0: none),
    /// keep() throws MemoryLimitError before copying.
    struct Budget {
        std::uint64_t limit = 0;
        std::uint64_t fixed = 0;
        std::size_t per_node = 0, per_keep = 0;
    };
    explicit NodeStore(std::size_t max_nodes);
    NodeStore(std::size_t max_nodes, const Budget& budget);
    /// A copy of `nodes` in the store (std::logic_error past max_nodes: no tree needs more).
    std::span<const BvhBuildNode> keep(std::span<const BvhBuildNode> nodes);
    std::size_t bytes_used() const { return used_.load(std::memory_order_relaxed) * sizeof(BvhBuildNode); }

private:
    struct Free {
        void operator()(BvhBuildNode* p) const;
    };
    std::unique_ptr<BvhBuildNode, Free> data_;
    std::size_t capacity_ = 0;
    std::atomic<std::size_t> used_{0};
    Budget budget_;
    std::atomic<std::uint64_t> charged_{0};
};

/// The tree of subtrees built by the parallel recursion (see build_top_down).
struct Subtree {
    std::span<const BvhBuildNode> nodes;  ///< a chunk: its whole tree, root at 0; a top node: the root only
    std::unique_ptr<Subtree> child[2];
    std::size_t total = 0;  ///< nodes in the whole subtree
    bool is_chunk() const { return !child[0]; }
};
/// Places the subtrees into one BinaryBvh node array (parallel, offsets from subtree sizes).
/// Returns the bytes of the subtrees' nodes and records (for the peak-memory estimate).
std::size_t assemble(const Subtree& root, std::vector<BvhBuildNode>& out);

/// Splitter: `std::optional<SplitResult> operator()(std::span<BuildPrim>, const BuildTask&) const`,
/// nullopt for a leaf. It must be safe to call concurrently on disjoint ranges, always split a
/// range larger than cfg.max_leaf_size, and keep the recursion depth bounded.
template <class Splitter> class TopDownBuilder {
public:
    TopDownBuilder(BuildPrims&& input, const BvhBuildConfig& cfg, const Splitter& split)
        : in_(std::move(input)), cfg_(cfg), split_(split), prims_(in_.prims),
          store_(2 * std::max<std::size_t>(prims_.size(), 1) - 1, budget(in_, cfg)) {}

    BinaryBvh run() {
        BinaryBvh bvh;
        bvh.dropped_nonfinite = in_.dropped_nonfinite;
        if (prims_.empty()) return bvh;
        const BuildTask root{0, std::uint32_t(prims_.size()), 0, in_.bounds, in_.centroid_bounds};
        const std::unique_ptr<Subtree> tree = build(root);
        const std::size_t chunk_bytes = assemble(*tree, bvh.nodes);
        resize_prefaulted(bvh.prim_ids, prims_.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, prims_.size(), 65536), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) bvh.prim_ids[i] = prims_[i].id;
        });
        // The input, the chunks and the output (PrimRefs a caller made the input from are the caller's):
        // what budget() below counts as the build goes.
        bvh.build_peak_bytes = in_.memory_bytes() + chunk_bytes + bvh.nodes.capacity() * sizeof(BvhBuildNode) +
                               bvh.prim_ids.capacity() * sizeof(std::uint32_t);
        return bvh;
    }

private:
    std::unique_ptr<Subtree> build(const BuildTask& t) {
        auto s = std::make_unique<Subtree>();
        if (t.size() < parallel_threshold()) {
            // Scratch: freed right after, so the thread's heap hands the same pages to its next chunk.
            std::vector<BvhBuildNode> nodes;
            nodes.reserve(2 * std::size_t(t.size()) - 1);  // a binary tree over n leaves' worth of prims
            nodes.push_back({});
            build_serial(t, 0, nodes);
            s->nodes = store_.keep(nodes);
            s->total = s->nodes.size();
            return s;
        }
        const std::optional<SplitResult> cut = split_(prims_, t);
        const BvhBuildNode root{t.box, cut ? 0u : t.begin, cut ? 0u : t.size()};
        s->nodes = store_.keep({&root, 1});
        if (!cut) {
            s->total = 1;
            return s;
        }
        const BuildTask left{t.begin, cut->mid, t.depth + 1, cut->left_box, cut->left_cbox};
        const BuildTask right{cut->mid, t.end, t.depth + 1, cut->right_box, cut->right_cbox};
        tbb::parallel_invoke([&] { s->child[0] = build(left); }, [&] { s->child[1] = build(right); });
        // A throw elsewhere in the build (the node budget, an allocation) cancels this branch's
        // tasks, and a wait on a cancelled task returns without throwing: the exception reaches the
        // caller through the branch that threw, so this one just stops.
        if (!s->child[0] || !s->child[1]) return s;
        s->total = 1 + s->child[0]->total + s->child[1]->total;
        return s;
    }

    void build_serial(const BuildTask& t, std::uint32_t node, std::vector<BvhBuildNode>& nodes) {
        nodes[node].box = t.box;
        const std::optional<SplitResult> cut = split_(prims_, t);
        if (!cut) {
            nodes[node].first = t.begin;
            nodes[node].count = t.size();
            return;
        }
        const auto first = std::uint32_t(nodes.size());
        nodes[node].first = first;
        nodes[node].count = 0;
        nodes.resize(nodes.size() + 2);
        build_serial({t.begin, cut->mid, t.depth + 1, cut->left_box, cut->left_cbox}, first, nodes);
        build_serial({cut->mid, t.end, t.depth + 1, cut->right_box, cut->right_cbox}, first + 1, nodes);
    }

    std::uint32_t parallel_threshold() const { return std::max<std::uint32_t>(cfg_.parallel_threshold, 2); }

    /// The peak run() reports, counted as it grows: the input and the ids from the start; per kept
    /// node its copy in the store and in the output, per keep() its Subtree record.
    static NodeStore::Budget budget(const BuildPrims& in, const BvhBuildConfig& cfg) {
        return {cfg.max_bytes, in.memory_bytes() + in.prims.size() * sizeof(std::uint32_t), 2 * sizeof(BvhBuildNode),
                sizeof(Subtree)};
    }

    BuildPrims in_;
    const BvhBuildConfig& cfg_;
    const Splitter& split_;
    UninitVector<BuildPrim>& prims_;
    NodeStore store_;
};

/// Runs the frame with `split` over `input` (consumed: partitioned in place).
template <class Splitter> BinaryBvh build_top_down(BuildPrims&& input, const BvhBuildConfig& cfg, const Splitter& split) {
    return TopDownBuilder<Splitter>(std::move(input), cfg, split).run();
}

}  // namespace arbor::accel::detail
