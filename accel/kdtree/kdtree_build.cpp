#include "accel/kdtree/kdtree_build.h"

#include "accel/core/memory_limit.h"

#include "accel/util/fp_guard.h"
#include "accel/kdtree/kdtree_ropes.h"
#include "accel/kdtree/kdtree_split.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>

namespace arbor::accel {

std::uint32_t kd_depth_limit(std::size_t n) {
    if (n < 2) return 0;
    const double limit = 8.0 + 1.3 * std::log2(double(n));
    return std::min<std::uint32_t>(kd_max_depth, std::uint32_t(limit));
}

namespace {

using kd::NodeWork;

/// Current and peak bytes of build temporaries (accounting only; placement never depends on it).
struct MemoryMeter {
    std::atomic<std::size_t> current{0}, peak{0};
    std::size_t limit = 0;  // BuildConfig::max_memory; 0 = none
    void add(std::size_t b) {
        const std::size_t now = current.fetch_add(b) + b;
        if (limit != 0 && now > limit)
            throw MemoryLimitError("kdtree: the build needs more than max_memory = " + std::to_string(limit) + " bytes");
        std::size_t p = peak.load();
        while (now > p && !peak.compare_exchange_weak(p, now)) {}
    }
    void sub(std::size_t b) { current.fetch_sub(b); }
};

/// A part of the output tree, laid out depth-first with indices relative to its own arrays.
struct Subtree {
    std::vector<KdNode> nodes;
    std::vector<KdLeaf> leaves;
    std::vector<std::uint32_t> refs;  // build triangle numbers

    /// Appends `s` after the current contents, shifting its node, leaf and ref indices.
    void append(const Subtree& s) {
        const auto node_off = std::uint32_t(nodes.size()), leaf_off = std::uint32_t(leaves.size());
        const auto ref_off = std::uint32_t(refs.size());
        for (KdNode n : s.nodes)
            nodes.push_back(n.is_leaf() ? KdNode::leaf(n.index() + leaf_off)
                                        : KdNode::interior(n.axis(), n.split, n.index() + node_off));
        for (KdLeaf l : s.leaves) {
            l.first += ref_off;
            leaves.push_back(l);
        }
        refs.insert(refs.end(), s.refs.begin(), s.refs.end());
    }
};

struct Builder {
    const kd::BuildTriangles& tris;
    kd::SahCosts costs;
    bool perfect_splits;
    std::uint32_t depth_limit;
    std::size_t parallel_threshold;
    std::size_t exact_below;
    MemoryMeter& meter;
    tbb::enumerable_thread_specific<kd::SplitScratch>& scratch;

    void make_leaf(const NodeWork& w, Subtree& out) const {
        KdLeaf leaf;
        leaf.box = w.box;
        leaf.first = std::uint32_t(out.refs.size());
        leaf.count = std::uint32_t(w.size());
        out.refs.insert(out.refs.end(), w.ids(), w.ids() + w.size());
        out.nodes.push_back(KdNode::leaf(std::uint32_t(out.leaves.size())));
        out.leaves.push_back(leaf);
    }

    kd::Split find_split(const NodeWork& w) const {
        if (w.has_events() && w.size() < parallel_threshold) return kd::find_split(w, costs);
        // Big nodes search the three axes in parallel; the reduction keeps the serial order.
        kd::Split s[3];
        tbb::parallel_for(0, 3, [&](int k) {
            const IeeeFpGuard guard;
            s[k] = w.has_events() ? kd::find_split_on_axis(w, k, costs) : kd::find_split_binned(w, k, costs);
        });
        kd::Split best;
        for (const kd::Split& c : s)
            if (c.axis >= 0 && (best.axis < 0 || c.cost < best.cost)) best = c;
        return best;
    }

    /// Builds the subtree of `w` (consumed) at `depth`, appending it to `out`.
    void build(NodeWork& w, std::uint32_t depth, Subtree& out) const {
        kd::Split s;
        if (depth < depth_limit) s = find_split(w);
        if (s.axis < 0 || !(s.cost < costs.intersection * double(w.size()))) {
            make_leaf(w, out);
            release(w);
            return;
        }
        NodeWork left, right;
        kd::SplitScratch& sc = scratch.local();
        const std::size_t scratch_before = sc.bytes();
        kd::split_node(w, s, tris, perfect_splits, sc, left, right);
        for (NodeWork* c : {&left, &right})
            if (!c->has_events() && c->size() <= exact_below) kd::make_events(*c);
        meter.add(left.bytes() + right.bytes() + (sc.bytes() - scratch_before));
        const std::size_t n = w.size();
        release(w);
        const auto me = std::uint32_t(out.nodes.size());
        out.nodes.emplace_back();
        std::uint32_t right_index = 0;
        if (n >= parallel_threshold) {
            Subtree ls, rs;
            tbb::parallel_invoke(
                [&] {
                    const IeeeFpGuard guard;
                    build(left, depth + 1, ls);
                },
                [&] {
                    const IeeeFpGuard guard;
                    build(right, depth + 1, rs);
                });
            out.append(ls);
            right_index = std::uint32_t(out.nodes.size());
            out.append(rs);
        } else {
            build(left, depth + 1, out);
            right_index = std::uint32_t(out.nodes.size());
            build(right, depth + 1, out);
        }
        if (out.nodes.size() > kd_max_index || out.leaves.size() > kd_max_index)
            throw std::length_error("kdtree: more than 2^30 nodes");
        out.nodes[me] = KdNode::interior(s.axis, s.pos, right_index);
    }

    void release(NodeWork& w) const {
        meter.sub(w.bytes());
        w = NodeWork{};
    }
};

}  // namespace

KdTree build_kdtree(const TriangleView& view, const KdBuildConfig& cfg, std::uint64_t max_memory) {
    const IeeeFpGuard guard;
    KdTree tree;
    const std::size_t count = view.triangle_count();

    // Finite triangles, in input order; build numbers index `finite`.
    std::vector<std::uint32_t> finite;
    finite.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        if (view.triangle_is_finite(i)) finite.push_back(std::uint32_t(i));
        else ++tree.dropped_nonfinite;
    }
    const std::size_t n = finite.size();
    if (n == 0) {
        tree.nodes.push_back(KdNode::leaf(0));
        tree.leaves.emplace_back();
        return tree;
    }
    if (n > kd_max_index) throw std::length_error("kdtree: more than 2^30 triangles");

    MemoryMeter meter;
    meter.limit = max_memory;
    kd::BuildTriangles tris;
    tris.v.resize(3 * n);
    NodeWork root(n, false);
    std::uint32_t* ids = root.ids();
    Bounds* boxes = root.boxes();
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        for (int k = 0; k < 3; ++k) tris.v[3 * i + k] = view.corner(finite[i], k);
        ids[i] = std::uint32_t(i);
        boxes[i] = view.triangle_bounds(finite[i]);
    });
    for (std::size_t i = 0; i < n; ++i) root.box.grow(boxes[i]);
    if (n <= cfg.exact_below) {
        root.allocate_events();
        tbb::parallel_for(0, 3, [&](int k) {
            const IeeeFpGuard task_guard;
            kd::Event* e = root.events(k);
            for (std::size_t i = 0; i < n; ++i) e = kd::put_events(e, boxes[i], k, std::uint32_t(i));
            root.set_event_count(k, std::size_t(e - root.events(k)));
            std::sort(root.events(k), e);
        });
    }
    meter.add(root.bytes() + tris.v.capacity() * sizeof(Vec3f) + finite.capacity() * sizeof(std::uint32_t));

    tree.box = root.box;
    tree.depth_limit = kd_depth_limit(n);
    tbb::enumerable_thread_specific<kd::SplitScratch> scratch;
    const Builder builder{tris,
                          {double(cfg.traversal_cost), double(cfg.intersection_cost), double(cfg.empty_bonus)},
                          cfg.perfect_splits,
                          tree.depth_limit,
                          std::max<std::size_t>(cfg.parallel_threshold, 1),
                          cfg.exact_below,
                          meter,
                          scratch};
    Subtree out;
    builder.build(root, 0, out);

    // Store every triangle once, in the order of its first reference; refs point into the store.
    std::vector<std::uint32_t> slot(n, 0xFFFFFFFFu);
    tree.tris.reserve(n);
    for (std::uint32_t& r : out.refs) {
        if (slot[r] == 0xFFFFFFFFu) {
            slot[r] = std::uint32_t(tree.tris.size());
            tree.tris.push_back({tris.corner(r, 0), tris.corner(r, 1), tris.corner(r, 2), finite[r]});
        }
        r = slot[r];
    }
    tree.nodes = std::move(out.nodes);
    tree.leaves = std::move(out.leaves);
    tree.refs = std::move(out.refs);
    compute_ropes(tree);
    tree.build_peak_bytes = meter.peak.load();
    return tree;
}

KdTreeStats kd_tree_stats(const KdTree& tree, float traversal_cost, float intersection_cost) {
    KdTreeStats st;
    st.nodes = tree.nodes.size();
    st.leaves = tree.leaves.size();
    st.refs = tree.refs.size();
    const double root_area = tree.box.area();
    double cost = 0.0, depth_sum = 0.0;
    struct Item {
        std::uint32_t node, depth;
        Bounds box;
    };
    std::vector<Item> stack{{0, 0, tree.box}};
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        const KdNode n = tree.nodes[it.node];
        if (n.is_leaf()) {
            const KdLeaf& l = tree.leaves[n.index()];
            cost += double(intersection_cost) * it.box.area() * l.count;
            st.max_depth = std::max(st.max_depth, it.depth);
            st.max_leaf_size = std::max(st.max_leaf_size, l.count);
            st.empty_leaves += l.count == 0;
            depth_sum += it.depth;
            continue;
        }
        cost += double(traversal_cost) * it.box.area();
        Bounds lb = it.box, rb = it.box;
        lb.hi[n.axis()] = n.split;
        rb.lo[n.axis()] = n.split;
        stack.push_back({n.index(), it.depth + 1, rb});
        stack.push_back({it.node + 1, it.depth + 1, lb});
    }
    st.mean_leaf_depth = st.leaves ? depth_sum / double(st.leaves) : 0.0;
    st.sah_cost = root_area > 0.0 ? cost / root_area : cost;
    return st;
}

}  // namespace arbor::accel
