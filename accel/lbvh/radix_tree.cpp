#include "accel/lbvh/radix_tree.h"

#include "accel/bvh/bvh_top_down.h"
#include "accel/util/prefault.h"
#include "accel/util/scratch_array.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <memory>
#include <optional>
#include <stdexcept>

namespace arbor::accel {

namespace {

/// One internal radix-tree node, named by its Karras index. Trivially constructible on purpose:
/// the array is allocated without a zeroing pass and every field is written before it is read.
struct InnerNode {
    Vec3f lo, hi;
    std::uint32_t split;  ///< gamma: the left child covers [first, gamma], the right [gamma + 1, last]
    std::uint32_t count;  ///< nodes of the collapsed subtree in the output (1 when it became a leaf)
    float cost;           ///< SAH cost of the collapsed subtree (unnormalized; sah_collapse only)
};

/// Box, output node count and SAH cost of a subtree.
struct Subtree {
    Bounds box;
    std::uint32_t count;
    float cost;
};

float area(const Bounds& b) { return float(b.area()); }

/// Length of the common prefix of the augmented keys at sorted positions i and j (a monotone
/// stand-in: code bits, then fine code bits, then position bits); -1 when j is outside [0, n).
class Delta {
public:
    Delta(const RadixTreeInput& in)
        : keys_(in.keys.data()), fine_(in.fine_codes.empty() ? nullptr : in.fine_codes.data()),
          n_(std::int64_t(in.keys.size())), shift_(in.code_shift), mask_(fine_ ? ~refined_bit : ~std::uint64_t(0)) {}
    int operator()(std::int64_t i, std::int64_t j) const {
        if (j < 0 || j >= n_) return -1;
        const std::uint64_t a = (keys_[i] & mask_) >> shift_, b = (keys_[j] & mask_) >> shift_;
        if (a != b) return std::countl_zero(a ^ b);
        if (fine_ && (keys_[i] & refined_bit)) {
            const std::uint64_t fa = fine_[std::uint32_t(keys_[i])], fb = fine_[std::uint32_t(keys_[j])];
            if (fa != fb) return 64 + std::countl_zero(fa ^ fb);
        }
        return 128 + std::countl_zero(std::uint32_t(i ^ j));
    }

private:
    const std::uint64_t* keys_;
    const std::uint64_t* fine_;
    std::int64_t n_;
    int shift_;
    std::uint64_t mask_;
    static constexpr std::uint64_t refined_bit = std::uint64_t(1) << 62;
};

class TreeBuilder {
public:
    TreeBuilder(const RadixTreeInput& in, std::vector<std::uint32_t>& prim_ids)
        : in_(in), prims_(in.prims), prim_ids_(prim_ids), n_(std::uint32_t(in.keys.size())),
          m_(std::max<std::uint32_t>(in.max_leaf_size, 1)), delta_(in) {}

    std::size_t temp_bytes() const {
        return inner_.bytes() + first_.bytes() + last_.bytes() + inner_parent_.bytes() + leaf_parent_.bytes() + visits_.bytes();
    }

    /// Karras 2012, Figure 4: node i finds the direction of its range, the other end j by an
    /// exponential then a binary search, and its split gamma by a binary search. Then bounds
    /// bottom-up, with one visit counter per node.
    void karras() {
        inner_ = ScratchArray<InnerNode>(n_ - 1);
        first_ = ScratchArray<std::uint32_t>(n_ - 1);
        last_ = ScratchArray<std::uint32_t>(n_ - 1);
        inner_parent_ = ScratchArray<std::uint32_t>(n_ - 1);
        leaf_parent_ = ScratchArray<std::uint32_t>(n_);
        visits_ = ScratchArray<std::uint32_t>(n_ - 1);
        tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, std::int64_t(n_) - 1, 4096),
                          [&](const tbb::blocked_range<std::int64_t>& r) {
                              for (std::int64_t i = r.begin(); i != r.end(); ++i) karras_node(i);
                              std::fill(visits_.data() + r.begin(), visits_.data() + r.end(), 0u);
                          });
        // From every leaf, climb while this thread is the second to arrive at a node (so both
        // children are done). The counters only order the work: every value written is the same
        // whoever arrives second, and acq_rel makes the first arrival's writes visible.
        tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n_, 4096), [&](const tbb::blocked_range<std::uint32_t>& range) {
            for (std::uint32_t p = range.begin(); p != range.end(); ++p) {
                prim_ids_[p] = prims_[ref(p)].id;
                std::uint32_t node = leaf_parent_[p];
                while (std::atomic_ref<std::uint32_t>(visits_[node]).fetch_add(1, std::memory_order_acq_rel) == 1) {
                    const std::uint32_t first = first_[node], last = last_[node], g = inner_[node].split;
                    const Subtree l = child(g, first, g), r = child(g + 1, g + 1, last);
                    store(node, first, last, g, l, r);
                    if (node == 0) break;
                    node = inner_parent_[node];
                }
            }
        });
    }

    /// Top-down: the root covers [0, n - 1]; stops at subtrees of at most max_leaf_size
    /// primitives. The tree is written in the canonical layout straight away, in the frame of the
    /// top-down builders (bvh_top_down.h): ranges above the parallel threshold are top nodes whose
    /// halves are built as parallel tasks, smaller ones are built serially into their own node
    /// arrays, and detail::assemble places them at offsets from subtree sizes. The same nodes as
    /// emit() after karras(), without its n - 1 internal nodes of 36 bytes (a fresh array, touched
    /// on every page although a tree with leaves of up to 16 primitives uses one node in 8).
    /// Returns the bytes of the node arrays.
    std::size_t top_down(std::vector<BvhBuildNode>& nodes) {
        store_.emplace(2 * std::size_t(n_) - 1);  // every node of the radix tree at most once
        const Part root = top_part(0, n_ - 1);
        return detail::assemble(*root.tree, nodes);
    }

    /// Writes the collapsed tree in the canonical layout (after karras()).
    std::vector<BvhBuildNode> emit() const {
        std::vector<BvhBuildNode> nodes;
        resize_prefaulted(nodes, inner_[0].count);  // every node is written by emit_node
        emit_node(nodes, 0, 0, n_ - 1, 0, 1);
        return nodes;
    }

private:
    static std::uint32_t size(std::uint32_t first, std::uint32_t last) { return last - first + 1; }

    std::uint32_t ref(std::uint32_t p) const {
        return in_.sorted_refs.empty() ? std::uint32_t(in_.keys[p]) : in_.sorted_refs[p];
    }

    void karras_node(std::int64_t i) {
        const int d = delta_(i, i + 1) > delta_(i, i - 1) ? 1 : -1;
        const int delta_min = delta_(i, i - d);
        std::int64_t l_max = 2;
        while (delta_(i, i + l_max * d) > delta_min) l_max *= 2;
        std::int64_t l = 0;
        for (std::int64_t t = l_max / 2; t >= 1; t /= 2)
            if (delta_(i, i + (l + t) * d) > delta_min) l += t;
        const std::int64_t j = i + l * d;
        const int delta_node = delta_(i, j);
        std::int64_t s = 0;
        for (std::int64_t t = l;;) {
            t = (t + 1) / 2;
            if (delta_(i, i + (s + t) * d) > delta_node) s += t;
            if (t <= 1) break;
        }
        const std::uint32_t gamma = std::uint32_t(i + s * d + std::min(d, 0));
        const std::uint32_t first = std::uint32_t(std::min(i, j)), last = std::uint32_t(std::max(i, j));
        inner_[i].split = gamma;
        first_[i] = first;
        last_[i] = last;
        (first == gamma ? leaf_parent_[gamma] : inner_parent_[gamma]) = std::uint32_t(i);
        (last == gamma + 1 ? leaf_parent_[gamma + 1] : inner_parent_[gamma + 1]) = std::uint32_t(i);
    }

    /// The largest gamma in [first, last) whose prefix with `first` is longer than the node's.
    std::uint32_t find_split(std::uint32_t first, std::uint32_t last) const {
        const int node_prefix = delta_(first, last);
        std::uint32_t lo = first + 1, hi = last;  // smallest p with delta(first, p) <= node_prefix
        while (lo < hi) {
            const std::uint32_t mid = lo + (hi - lo) / 2;
            if (delta_(first, mid) > node_prefix) lo = mid + 1;
            else hi = mid;
        }
        return lo - 1;
    }

    /// A finished child: one primitive (read from the prim refs) or internal node idx.
    Subtree child(std::uint32_t idx, std::uint32_t first, std::uint32_t last) const {
        if (first == last) {
            const Bounds box = prims_[ref(first)].box();
            return {box, 1, in_.sah_collapse ? area(box) * in_.intersection_cost : 0.0f};
        }
        return {{inner_[idx].lo, inner_[idx].hi}, inner_[idx].count, inner_[idx].cost};
    }

    /// The subtree over [first, last] from its two children: its box, its output node count (1
    /// when a subtree of at most m_ primitives becomes one leaf) and its SAH cost.
    Subtree join(std::uint32_t first, std::uint32_t last, const Subtree& l, const Subtree& r) const {
        Bounds box = l.box;
        box.grow(r.box);
        const std::uint32_t n = size(first, last);
        std::uint32_t count = n <= m_ ? 1u : 1u + l.count + r.count;
        float cost = 0.0f;
        if (in_.sah_collapse) {
            const float a = area(box), split_cost = a * in_.traversal_cost + l.cost + r.cost;
            const float leaf_cost = a * float(n) * in_.intersection_cost;
            count = n <= m_ && leaf_cost <= split_cost ? 1u : 1u + l.count + r.count;
            cost = count == 1 ? leaf_cost : split_cost;
        }
        return {box, count, cost};
    }

    /// Records internal node idx from its two children (join).
    Subtree store(std::uint32_t idx, std::uint32_t first, std::uint32_t last, std::uint32_t g, const Subtree& l,
                  const Subtree& r) {
        const Subtree s = join(first, last, l, r);
        InnerNode& node = inner_[idx];
        node.lo = s.box.lo, node.hi = s.box.hi;
        node.split = g;
        node.count = s.count;
        node.cost = s.cost;
        return s;
    }

    /// A range that is a leaf for sure: at most m_ primitives (without the SAH collapse), or one.
    /// With the SAH collapse, a small range is built as a subtree and store() decides.
    bool leaf_range(std::uint32_t first, std::uint32_t last) const {
        return size(first, last) <= m_ && (!in_.sah_collapse || first == last);
    }

    /// A leaf's box and triangle ids are all it needs.
    Subtree leaf(std::uint32_t first, std::uint32_t last) {
        Bounds box;
        for (std::uint32_t p = first; p <= last; ++p) {
            const BuildPrim& prim = prims_[ref(p)];
            box.grow(prim.box());
            prim_ids_[p] = prim.id;
        }
        return {box, 1, in_.sah_collapse ? area(box) * in_.intersection_cost : 0.0f};
    }

    /// A subtree of the top-down build: its tree for detail::assemble and its box, count and cost.
    struct Part {
        std::unique_ptr<detail::Subtree> tree;
        Subtree sub;
    };

    /// [first, last] above the parallel threshold: a top node with its halves built in parallel;
    /// else a chunk built serially.
    Part top_part(std::uint32_t first, std::uint32_t last) {
        Part part;
        part.tree = std::make_unique<detail::Subtree>();
        detail::Subtree& t = *part.tree;
        if (leaf_range(first, last) || size(first, last) <= in_.parallel_threshold) {
            std::vector<BvhBuildNode> nodes(1);  // scratch (the thread's heap reuses its pages for the next chunk)
            part.sub = chunk_node(nodes, 0, first, last);
            t.nodes = store_->keep(nodes);
            t.total = t.nodes.size();
            return part;
        }
        const std::uint32_t g = find_split(first, last);
        Part l, r;
        tbb::parallel_invoke([&] { l = top_part(first, g); }, [&] { r = top_part(g + 1, last); });
        part.sub = join(first, last, l.sub, r.sub);
        if (part.sub.count == 1) {  // collapsed (sah_collapse): a leaf after all
            const BvhBuildNode leaf_node{part.sub.box, first, size(first, last)};
            t.nodes = store_->keep({&leaf_node, 1});
            t.total = 1;
            return part;
        }
        const BvhBuildNode node{part.sub.box, 0, 0};
        t.nodes = store_->keep({&node, 1});
        t.child[0] = std::move(l.tree);
        t.child[1] = std::move(r.tree);
        t.total = 1 + t.child[0]->total + t.child[1]->total;
        return part;
    }

    /// Node `at` of a chunk over [first, last], its descendants appended (children side by side,
    /// each subtree contiguous after them, so a collapsed subtree is cut off the end).
    Subtree chunk_node(std::vector<BvhBuildNode>& nodes, std::uint32_t at, std::uint32_t first, std::uint32_t last) {
        if (leaf_range(first, last)) {
            const Subtree s = leaf(first, last);
            nodes[at] = {s.box, first, size(first, last)};
            return s;
        }
        const std::uint32_t g = find_split(first, last);
        const auto kids = std::uint32_t(nodes.size());
        nodes.resize(kids + 2);
        const Subtree l = chunk_node(nodes, kids, first, g), r = chunk_node(nodes, kids + 1, g + 1, last);
        const Subtree s = join(first, last, l, r);
        if (s.count == 1) {
            nodes.resize(kids);
            nodes[at] = {s.box, first, size(first, last)};
        } else {
            nodes[at] = {s.box, kids, 0};
        }
        return s;
    }

    /// Writes node idx (range [first, last]) at `out`; its descendants go from `desc` on.
    void emit_node(std::vector<BvhBuildNode>& nodes, std::uint32_t idx, std::uint32_t first, std::uint32_t last,
                   std::uint32_t out, std::uint32_t desc) const {
        BvhBuildNode& node = nodes[out];
        const std::uint32_t count = size(first, last);
        node.box = child(idx, first, last).box;
        if (count == 1 || inner_[idx].count == 1) {  // a primitive or a collapsed subtree
            node.first = first;
            node.count = count;
            return;
        }
        node.first = desc;
        node.count = 0;
        const std::uint32_t g = inner_[idx].split;
        const std::uint32_t left_nodes = g == first ? 1u : inner_[g].count;
        auto left = [&] { emit_node(nodes, g, first, g, desc, desc + 2); };
        auto right = [&] { emit_node(nodes, g + 1, g + 1, last, desc + 1, desc + 2 + left_nodes - 1); };
        if (count > in_.parallel_threshold) tbb::parallel_invoke(left, right);
        else left(), right();
    }

    const RadixTreeInput& in_;
    std::span<const BuildPrim> prims_;
    std::vector<std::uint32_t>& prim_ids_;
    std::uint32_t n_, m_;
    Delta delta_;
    ScratchArray<InnerNode> inner_;  ///< Karras only
    std::optional<detail::NodeStore> store_;  ///< top-down only
    // Karras only: each internal node's range, parent and visit counter, each primitive's parent.
    ScratchArray<std::uint32_t> first_, last_, inner_parent_, leaf_parent_, visits_;
};

}  // namespace

RadixTreeResult build_radix_tree(const RadixTreeInput& in, RadixTreeMethod method) {
    if (in.prims.size() < in.keys.size()) throw std::invalid_argument("build_radix_tree: fewer prims than keys");
    if (!in.sorted_refs.empty() && in.sorted_refs.size() != in.keys.size())
        throw std::invalid_argument("build_radix_tree: sorted_refs and keys differ in size");
    if (!in.fine_codes.empty() && (!in.sorted_refs.empty() || in.code_shift != 32 || in.fine_codes.size() != in.prims.size()))
        throw std::invalid_argument("build_radix_tree: fine codes need the references in the keys, one per reference");
    if (in.keys.size() >= std::size_t(1) << 31) throw std::invalid_argument("build_radix_tree: too many primitives");
    RadixTreeResult result;
    const std::uint32_t n = std::uint32_t(in.keys.size());
    if (n == 0) return result;
    resize_prefaulted(result.prim_ids, n);
    if (n == 1) {
        const std::uint32_t r = in.sorted_refs.empty() ? std::uint32_t(in.keys[0]) : in.sorted_refs[0];
        result.prim_ids[0] = in.prims[r].id;
        result.nodes.push_back({in.prims[r].box(), 0, 1});
        return result;
    }
    TreeBuilder builder(in, result.prim_ids);
    if (method == RadixTreeMethod::karras) {
        builder.karras();
        result.temp_bytes = builder.temp_bytes();
        result.nodes = builder.emit();
    } else {
        result.temp_bytes = builder.top_down(result.nodes);
    }
    return result;
}

}  // namespace arbor::accel
