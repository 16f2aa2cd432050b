#include "accel/radix_tree.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <memory>
#include <stdexcept>

namespace arbor::accel {

namespace {

/// One internal radix-tree node, named by its Karras index. Trivially constructible on purpose:
/// the array is allocated without a zeroing pass and every field is written before it is read.
struct InnerNode {
    Vec3f lo, hi;
    std::uint32_t split;  ///< gamma: the left child covers [first, gamma], the right [gamma + 1, last]
    std::uint32_t count;  ///< nodes of the collapsed subtree in the output (1 when it became a leaf)
};
static_assert(std::is_trivially_default_constructible_v<InnerNode>);

/// Length of the common prefix of the augmented keys at sorted positions i and j; -1 when j is
/// outside [0, n).
class Delta {
public:
    Delta(std::span<const std::uint64_t> keys, int shift) : keys_(keys.data()), n_(std::int64_t(keys.size())), shift_(shift) {}
    int operator()(std::int64_t i, std::int64_t j) const {
        if (j < 0 || j >= n_) return -1;
        const std::uint64_t a = keys_[i] >> shift_, b = keys_[j] >> shift_;
        if (a != b) return std::countl_zero(a ^ b);
        return 64 + std::countl_zero(std::uint32_t(i ^ j));
    }

private:
    const std::uint64_t* keys_;
    std::int64_t n_;
    int shift_;
};

Bounds box_of(const InnerNode& n) { return {n.lo, n.hi}; }

class TreeBuilder {
public:
    explicit TreeBuilder(const RadixTreeInput& in)
        : in_(in), n_(std::uint32_t(in.keys.size())), m_(std::max<std::uint32_t>(in.max_leaf_size, 1)),
          delta_(in.keys, in.code_shift), inner_(new InnerNode[n_ - 1]) {}

    std::size_t inner_bytes() const { return std::size_t(n_ - 1) * sizeof(InnerNode); }

    /// Karras 2012, Figure 4: node i finds the direction of its range, the other end j by an
    /// exponential then a binary search, and its split gamma by a binary search.
    void karras() {
        first_.reset(new std::uint32_t[n_ - 1]);
        last_.reset(new std::uint32_t[n_ - 1]);
        inner_parent_.reset(new std::uint32_t[n_ - 1]);
        leaf_parent_.reset(new std::uint32_t[n_]);
        tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, std::int64_t(n_) - 1, 4096),
                          [&](const tbb::blocked_range<std::int64_t>& r) {
                              for (std::int64_t i = r.begin(); i != r.end(); ++i) karras_node(i);
                          });
        // Bottom-up: from every leaf, climb while this thread is the second to arrive at a node (so
        // both children are done). The visit counters only order the work: every value written is
        // the same whoever arrives second.
        std::unique_ptr<std::atomic<std::uint32_t>[]> visits(new std::atomic<std::uint32_t>[n_ - 1]);
        tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n_ - 1, 16384), [&](const tbb::blocked_range<std::uint32_t>& r) {
            for (std::uint32_t i = r.begin(); i != r.end(); ++i) visits[i].store(0, std::memory_order_relaxed);
        });
        tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n_, 4096), [&](const tbb::blocked_range<std::uint32_t>& r) {
            for (std::uint32_t p = r.begin(); p != r.end(); ++p) {
                std::uint32_t node = leaf_parent_[p];
                while (visits[node].fetch_add(1, std::memory_order_acq_rel) == 1) {
                    finish(node, first_[node], last_[node]);
                    if (node == 0) break;
                    node = inner_parent_[node];
                }
            }
        });
    }

    /// Top-down: root covers [0, n - 1]; recursion in parallel above the threshold.
    void top_down() { top_down_node(0, 0, n_ - 1); }

    /// Writes the collapsed tree in the canonical layout.
    std::vector<BvhBuildNode> emit() {
        std::vector<BvhBuildNode> nodes(inner_[0].count);
        emit_node(nodes, 0, 0, n_ - 1, 0, 1);
        return nodes;
    }

    std::size_t karras_bytes() const { return std::size_t(n_ - 1) * 4 * sizeof(std::uint32_t) + std::size_t(n_) * 4; }

private:
    std::uint32_t size(std::uint32_t first, std::uint32_t last) const { return last - first + 1; }

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

    /// Box and output node count of a child range (a single primitive or an internal node).
    Bounds child_box(std::uint32_t idx, std::uint32_t first, std::uint32_t last) const {
        return first == last ? in_.boxes[first] : box_of(inner_[idx]);
    }
    std::uint32_t child_count(std::uint32_t idx, std::uint32_t first, std::uint32_t last) const {
        return first == last ? 1u : inner_[idx].count;
    }

    /// Box and count of internal node idx from its children (both finished).
    void finish(std::uint32_t idx, std::uint32_t first, std::uint32_t last) {
        InnerNode& node = inner_[idx];
        const std::uint32_t g = node.split;
        Bounds box = child_box(g, first, g);
        box.grow(child_box(g + 1, g + 1, last));
        node.lo = box.lo, node.hi = box.hi;
        node.count = size(first, last) <= m_ ? 1u : 1u + child_count(g, first, g) + child_count(g + 1, g + 1, last);
    }

    void top_down_node(std::uint32_t idx, std::uint32_t first, std::uint32_t last) {
        InnerNode& node = inner_[idx];
        if (size(first, last) <= m_) {  // a leaf: its box is all that is needed
            Bounds box;
            for (std::uint32_t p = first; p <= last; ++p) box.grow(in_.boxes[p]);
            node.lo = box.lo, node.hi = box.hi;
            node.count = 1;
            return;
        }
        const std::uint32_t g = find_split(first, last);
        node.split = g;
        auto left = [&] { if (g > first) top_down_node(g, first, g); };
        auto right = [&] { if (g + 1 < last) top_down_node(g + 1, g + 1, last); };
        if (size(first, last) > in_.parallel_threshold) tbb::parallel_invoke(left, right);
        else left(), right();
        finish(idx, first, last);
    }

    /// Writes node idx (range [first, last]) at `out`; its descendants go from `desc` on.
    void emit_node(std::vector<BvhBuildNode>& nodes, std::uint32_t idx, std::uint32_t first, std::uint32_t last,
                   std::uint32_t out, std::uint32_t desc) const {
        BvhBuildNode& node = nodes[out];
        node.box = child_box(idx, first, last);
        const std::uint32_t count = size(first, last);
        if (count <= m_) {
            node.first = first;
            node.count = count;
            return;
        }
        node.first = desc;
        node.count = 0;
        const std::uint32_t g = inner_[idx].split;
        const std::uint32_t left_nodes = child_count(g, first, g);
        auto left = [&] { emit_node(nodes, g, first, g, desc, desc + 2); };
        auto right = [&] { emit_node(nodes, g + 1, g + 1, last, desc + 1, desc + 2 + left_nodes - 1); };
        if (count > in_.parallel_threshold) tbb::parallel_invoke(left, right);
        else left(), right();
    }

    const RadixTreeInput& in_;
    std::uint32_t n_, m_;
    Delta delta_;
    std::unique_ptr<InnerNode[]> inner_;
    // Karras only: each internal node's range and parent, each primitive's parent.
    std::unique_ptr<std::uint32_t[]> first_, last_, inner_parent_, leaf_parent_;
};

}  // namespace

RadixTreeResult build_radix_tree(const RadixTreeInput& in, RadixTreeMethod method) {
    if (in.keys.size() != in.boxes.size()) throw std::invalid_argument("build_radix_tree: keys and boxes differ in size");
    if (in.keys.size() >= std::size_t(1) << 31) throw std::invalid_argument("build_radix_tree: too many primitives");
    RadixTreeResult result;
    const std::uint32_t n = std::uint32_t(in.keys.size());
    if (n == 0) return result;
    if (n == 1) {
        result.nodes.push_back({in.boxes[0], 0, 1});
        return result;
    }
    TreeBuilder builder(in);
    result.temp_bytes = builder.inner_bytes();
    if (method == RadixTreeMethod::karras) {
        builder.karras();
        result.temp_bytes += builder.karras_bytes();
    } else {
        builder.top_down();
    }
    result.nodes = builder.emit();
    return result;
}

}  // namespace arbor::accel
