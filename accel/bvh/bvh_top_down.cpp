#include "accel/bvh/bvh_top_down.h"
#include "accel/core/memory_limit.h"
#include "accel/util/prefault.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <new>
#include <stdexcept>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace arbor::accel::detail {

SplitResult bounds_of_halves(std::span<const BuildPrim> prims, std::uint32_t begin, std::uint32_t mid, std::uint32_t end) {
    SplitResult s;
    s.mid = mid;
    for (std::uint32_t i = begin; i < end; ++i) {
        const BuildPrim& p = prims[i];
        const Vec3f c{p.centroid(0), p.centroid(1), p.centroid(2)};
        if (i < mid) s.left_box.grow(p.box()), s.left_cbox.grow(c);
        else s.right_box.grow(p.box()), s.right_cbox.grow(c);
    }
    return s;
}

SplitResult index_median_split(std::span<BuildPrim> prims, const BuildTask& t) {
    return bounds_of_halves(prims, t.begin, t.begin + t.size() / 2, t.end);
}

SplitResult object_median_split(std::span<BuildPrim> prims, const BuildTask& t, int axis) {
    const std::uint32_t mid = t.begin + t.size() / 2;
    std::nth_element(prims.begin() + t.begin, prims.begin() + mid, prims.begin() + t.end,
                     [axis](const BuildPrim& a, const BuildPrim& b) { return a.centroid(axis) < b.centroid(axis); });
    return bounds_of_halves(prims, t.begin, mid, t.end);
}

int longest_axis(const Bounds& cbox) {
    int best = -1;
    double extent = 0.0;
    for (int a = 0; a < 3; ++a) {
        const double e = double(cbox.hi[a]) - double(cbox.lo[a]);
        if (e > extent) extent = e, best = a;
    }
    return best;
}

NodeStore::NodeStore(std::size_t max_nodes) : NodeStore(max_nodes, Budget{}) {}

NodeStore::NodeStore(std::size_t max_nodes, const Budget& budget) : capacity_(max_nodes), budget_(budget) {
    constexpr std::size_t huge = std::size_t(2) << 20;
    const std::size_t bytes = std::max<std::size_t>(max_nodes, 1) * sizeof(BvhBuildNode);
    const std::size_t align = bytes >= huge ? huge : alignof(std::max_align_t);
    void* p = std::aligned_alloc(align, (bytes + align - 1) / align * align);  // reserved: pages mapped when written
    if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes >= huge) madvise(p, bytes, MADV_HUGEPAGE);  // advice only: failure changes nothing
#endif
    data_.reset(static_cast<BvhBuildNode*>(p));
}

void NodeStore::Free::operator()(BvhBuildNode* p) const { std::free(p); }

std::span<const BvhBuildNode> NodeStore::keep(std::span<const BvhBuildNode> nodes) {
    if (budget_.limit != 0) {
        const std::uint64_t add = nodes.size() * budget_.per_node + budget_.per_keep;
        const std::uint64_t total = budget_.fixed + charged_.fetch_add(add, std::memory_order_relaxed) + add;
        if (total > budget_.limit)
            throw MemoryLimitError("building its binary tree went past " + max_memory_text(budget_.limit) +
                                   ": its primitives, ids and the nodes made so far need " + mib_text(total));
    }
    const std::size_t at = used_.fetch_add(nodes.size(), std::memory_order_relaxed);
    if (at + nodes.size() > capacity_) throw std::logic_error("NodeStore: more nodes than a binary tree over the primitives has");
    std::copy(nodes.begin(), nodes.end(), data_.get() + at);
    return {data_.get() + at, nodes.size()};
}

namespace {

/// Subtrees of at least this many nodes are placed by two parallel tasks.
constexpr std::size_t parallel_place = 4096;

/// Writes subtree `s` with its root at out[slot] and its other nodes from out[region] on.
void place(const Subtree& s, std::uint32_t slot, std::uint32_t region, BvhBuildNode* out) {
    if (s.is_chunk()) {
        // Local node l >= 1 goes to region + l - 1; so does every child index.
        for (std::size_t l = 0; l < s.nodes.size(); ++l) {
            BvhBuildNode n = s.nodes[l];
            if (!n.is_leaf()) n.first = region + n.first - 1;
            out[l == 0 ? slot : region + l - 1] = n;
        }
        return;
    }
    BvhBuildNode root = s.nodes[0];
    root.first = region;
    out[slot] = root;
    const Subtree &a = *s.child[0], &b = *s.child[1];
    const auto left_region = region + 2, right_region = std::uint32_t(region + 2 + (a.total - 1));
    if (s.total >= parallel_place)
        tbb::parallel_invoke([&] { place(a, region, left_region, out); }, [&] { place(b, region + 1, right_region, out); });
    else
        place(a, region, left_region, out), place(b, region + 1, right_region, out);
}

std::size_t chunk_bytes(const Subtree& s) {
    if (s.is_chunk()) return sizeof(Subtree) + s.nodes.size() * sizeof(BvhBuildNode);
    return sizeof(Subtree) + sizeof(BvhBuildNode) + chunk_bytes(*s.child[0]) + chunk_bytes(*s.child[1]);
}

}  // namespace

std::size_t assemble(const Subtree& root, std::vector<BvhBuildNode>& out) {
    resize_prefaulted(out, root.total);
    place(root, 0, 1, out.data());
    return chunk_bytes(root);
}

}  // namespace arbor::accel::detail
