// The kd-tree's cells as a binary BVH (accel/structures/kdtree_cells.h) and its N-wide collapse:
// every non-empty kd leaf is one binary leaf, with its cell as box (tight: the cell cut to its
// triangles' bounds) and its triangles in order; no empty leaf; siblings adjacent, children after parents, boxes nested; every kd leaf's triangles
// reachable through the wide layout under boxes that hold its leaf's box, each wide leaf listing a
// triangle once; the same tree and answers with 1 and 2 threads. (validate_bvh does not apply:
// a triangle crossing a plane is in several leaves.) The paths themselves: kd_simd_check.h.
#include "accel/factory/make_accel.h"
#include "accel/kdtree/kdtree_build.h"
#include "accel/structures/kdtree_cells.h"
#include "accel/interface/trace.h"
#include "accel/wide/wide_layout.h"
#include "engine/builtin_scenes.h"
#include "engine/procedural.h"
#include "testing.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstring>
#include <set>
#include <vector>

using namespace arbor;
using accel::Bounds;
using accel::Hit;

namespace {

bool same_box(const Bounds& a, const Bounds& b) { return std::memcmp(&a, &b, sizeof(Bounds)) == 0; }

/// The non-empty kd leaves of `tree` in depth-first order, with their cells cut from the scene box.
struct CellLeaf {
    Bounds cell;
    std::vector<std::uint32_t> prims;
};
void kd_cells(const accel::KdTree& tree, std::uint32_t n, Bounds cell, std::vector<CellLeaf>& out) {
    const accel::KdNode& node = tree.nodes[n];
    if (node.is_leaf()) {
        const accel::KdLeaf& leaf = tree.leaves[node.index()];
        if (leaf.count == 0) return;
        CellLeaf c{cell, {}};
        for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) c.prims.push_back(tree.tris[tree.refs[i]].prim);
        out.push_back(std::move(c));
        return;
    }
    Bounds below = cell, above = cell;
    below.hi[node.axis()] = node.split;
    above.lo[node.axis()] = node.split;
    kd_cells(tree, n + 1, below, out);
    kd_cells(tree, node.index(), above, out);
}

/// Walks the binary tree from the root: each node reached once, children after their parent and
/// adjacent, boxes nested; its leaves in pre-order. Returns the number of problems.
std::size_t walk_binary(const accel::BinaryBvh& bvh, std::uint32_t i, std::vector<std::uint32_t>& seen,
                        std::vector<CellLeaf>& leaves) {
    std::size_t bad = seen[i]++ != 0;
    const accel::BvhBuildNode& n = bvh.nodes[i];
    if (n.is_leaf()) {
        leaves.push_back({n.box, {bvh.prim_ids.begin() + n.first, bvh.prim_ids.begin() + n.first + n.count}});
        return bad;
    }
    if (n.first <= i || n.first + 1 >= bvh.nodes.size()) return bad + 1;
    for (std::uint32_t c = n.first; c <= n.first + 1; ++c) {
        bad += !n.box.contains(bvh.nodes[c].box);
        bad += walk_binary(bvh, c, seen, leaves);
    }
    return bad;
}

/// A wide leaf: the boxes on its path (outermost first) and its triangles.
struct WideLeaf {
    Bounds box;
    std::vector<std::uint32_t> ids;
};
template <std::size_t N>
std::size_t walk_wide(const accel::WideLayout<N>& w, std::uint32_t node, const Bounds& parent, std::vector<WideLeaf>& out) {
    std::size_t bad = 0;
    const accel::WideNode<N>& n = w.nodes[node];
    for (std::size_t c = 0; c < n.children; ++c) {
        Bounds b;
        b.lo = accel::Vec3f{n.boxes.b[0][0][c], n.boxes.b[0][1][c], n.boxes.b[0][2][c]};
        b.hi = accel::Vec3f{n.boxes.b[1][0][c], n.boxes.b[1][1][c], n.boxes.b[1][2][c]};
        bad += !parent.contains(b);
        if (!n.is_leaf(c)) {
            bad += walk_wide(w, n.child[c], b, out);
            continue;
        }
        WideLeaf leaf{b, {}};
        for (std::uint32_t s = 0; s < accel::wide_blocks<N>(n.count[c]) * N; ++s) {
            const std::uint32_t id = w.blocks[n.child[c] + s / N].ids[s % N];
            if (id != accel::invalid_prim) leaf.ids.push_back(id);
        }
        out.push_back(std::move(leaf));
    }
    return bad;
}

/// The collapse of the cell tree at width N with `merge` (WideConfig::merge_triangles; 0: N; when
/// set, with triangle blocks priced low, so that subtrees are merged).
/// Returns the number of cells whose triangles sit in a leaf merged from several cells.
template <std::size_t N>
std::size_t check_wide(const accel::KdTree& tree, const accel::BinaryBvh& bvh, const std::vector<CellLeaf>& cells,
                       std::uint32_t merge = 0) {
    CAPTURE(N);
    CAPTURE(merge);
    const accel::KdPrimView prims = accel::kd_prim_view(tree);
    accel::WideConfig cfg;
    cfg.merge_triangles = merge;
    if (merge) cfg.block_cost = 0.01f;  // triangle tests priced low: the SAH merges what it may
    const accel::WideLayout<N> w = accel::make_wide_layout<N>(bvh, prims.view(), cfg);
    std::vector<std::uint32_t> tri_of(prims.indices.size() / 3, accel::invalid_prim);
    for (std::uint32_t i = 0; i < tree.tris.size(); ++i) tri_of[tree.tris[i].prim] = i;
    REQUIRE(!w.empty());
    std::vector<WideLeaf> leaves;
    CHECK(walk_wide(w, 0, bvh.nodes[0].box, leaves) == 0);
    CHECK(leaves.size() == w.leaves);
    // Each wide leaf lists a triangle once, in ascending prim order (the tie rule), with its own
    // corners from the tree.
    std::size_t repeated = 0, corners = 0, merged = 0;
    for (const WideLeaf& l : leaves) repeated += !std::is_sorted(l.ids.begin(), l.ids.end()) ||
                                                 std::adjacent_find(l.ids.begin(), l.ids.end()) != l.ids.end();
    for (std::size_t s = 0; s < w.blocks.size() * N; ++s) {
        const std::uint32_t id = w.prim(s);
        if (id == accel::invalid_prim) continue;
        if (id >= tri_of.size() || tri_of[id] == accel::invalid_prim) {
            ++corners;
            continue;
        }
        const accel::KdTriangle& t = tree.tris[tri_of[id]];
        const accel::Vec3f c[3] = {t.v0, t.v1, t.v2};
        for (int k = 0; k < 3; ++k) {
            const accel::Vec3f v = w.vertex(s, k);
            corners += std::memcmp(&c[k], &v, sizeof v) != 0 ? 1 : 0;
        }
    }
    CHECK(repeated == 0);
    CHECK(corners == 0);
    // Every kd leaf's triangles are reachable: some wide leaf whose box holds the cell lists them all.
    std::size_t unreachable = 0;
    for (const CellLeaf& c : cells) {
        bool found = false;
        for (const WideLeaf& l : leaves) {
            if (!l.box.contains(c.cell)) continue;
            found = std::includes(l.ids.begin(), l.ids.end(), c.prims.begin(), c.prims.end());
            if (found) {
                merged += !same_box(l.box, c.cell);
                break;
            }
        }
        unreachable += !found;
    }
    CHECK(unreachable == 0);
    return merged;
}

/// `tight`: the leaves' boxes are their cells cut to their triangles' bounds, interior boxes the
/// union of their children's; else the pure cells.
void check_cells(const engine::Mesh& mesh, bool tight) {
    CAPTURE(tight);
    const accel::KdTree tree = accel::build_kdtree(mesh.view());
    std::vector<CellLeaf> cells;
    kd_cells(tree, 0, tree.box, cells);
    std::vector<std::uint32_t> tri_of(mesh.triangle_count(), accel::invalid_prim);
    for (std::uint32_t i = 0; i < tree.tris.size(); ++i) tri_of[tree.tris[i].prim] = i;
    std::vector<Bounds> expect(cells.size());  // each binary leaf's box
    std::size_t smaller = 0;
    for (std::size_t i = 0; i < cells.size(); ++i) {
        expect[i] = cells[i].cell;
        if (!tight) continue;
        Bounds tris;
        for (std::uint32_t p : cells[i].prims) {
            const accel::KdTriangle& t = tree.tris[tri_of[p]];
            tris.grow(t.v0), tris.grow(t.v1), tris.grow(t.v2);
        }
        expect[i].lo = simd::vmax(expect[i].lo, tris.lo);
        expect[i].hi = simd::vmin(expect[i].hi, tris.hi);
        smaller += !same_box(expect[i], cells[i].cell);
    }
    CHECK((!tight || smaller > 0));
    std::size_t empty_leaves = 0;
    for (const accel::KdLeaf& l : tree.leaves) empty_leaves += l.count == 0;
    REQUIRE(empty_leaves > 0);  // the scenes have empty space: the conversion leaves it out
    const accel::BinaryBvh bvh = accel::kd_cell_bvh(tree, tight);
    REQUIRE(!bvh.nodes.empty());
    CHECK(tree.box.contains(bvh.nodes[0].box));
    CHECK((tight || same_box(bvh.nodes[0].box, tree.box)));
    std::vector<std::uint32_t> seen(bvh.nodes.size(), 0);
    std::vector<CellLeaf> leaves;
    CHECK(walk_binary(bvh, 0, seen, leaves) == 0);
    CHECK(std::count(seen.begin(), seen.end(), 1u) == std::ptrdiff_t(bvh.nodes.size()));  // every node once
    CHECK(bvh.nodes.size() == 2 * leaves.size() - 1);
    // The binary leaves are the non-empty kd leaves, in order, with the same cells and triangles.
    REQUIRE(leaves.size() == cells.size());
    CHECK(leaves.size() + empty_leaves == tree.leaves.size());
    std::size_t differ = 0, refs = 0;
    for (std::size_t i = 0; i < cells.size(); ++i) {
        differ += !same_box(leaves[i].cell, expect[i]) || leaves[i].prims != cells[i].prims || leaves[i].prims.empty();
        refs += cells[i].prims.size();
    }
    CHECK(differ == 0);
    CHECK(bvh.prim_ids.size() == refs);
    CHECK(bvh.prim_ids.size() == tree.refs.size());
    std::vector<CellLeaf> boxed = cells;  // the cells with their leaves' boxes
    for (std::size_t i = 0; i < cells.size(); ++i) boxed[i].cell = expect[i];
    check_wide<4>(tree, bvh, boxed);
    check_wide<8>(tree, bvh, boxed);
    check_wide<16>(tree, bvh, boxed);
    // Leaves merged from several cells (the default merges none here: the kd leaves are bigger
    // than N), where a triangle crossing a plane would be listed twice.
    CHECK(check_wide<8>(tree, bvh, boxed, 256) > 0);
}

}  // namespace

TEST_CASE("kdtree cells: every non-empty leaf once with its cell, nested boxes, reachable through the wide layout") {
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 2, 0.1f, 3);
    mesh.append(engine::make_torus({2.5f, 0.2f, -0.3f}, 1.0f, 0.25f, 24, 8));
    for (const bool tight : {false, true}) {
        check_cells(mesh, tight);
        check_cells(engine::make_builtin_scene("builtin:cornell").mesh, tight);
    }
}

TEST_CASE("kdtree cells: an empty tree has no cells, one triangle is one leaf") {
    const accel::KdTree empty;
    CHECK(accel::kd_cell_bvh(empty).nodes.empty());
    const float x[3] = {0, 1, 0}, y[3] = {0, 0, 1}, z[3] = {0, 0, 0};
    const std::uint32_t idx[3] = {0, 1, 2};
    const accel::KdTree one = accel::build_kdtree(accel::TriangleView{x, y, z, idx});
    const accel::BinaryBvh bvh = accel::kd_cell_bvh(one);
    REQUIRE(bvh.nodes.size() == 1);
    CHECK(bvh.nodes[0].count == 1);
    CHECK(bvh.prim_ids == std::vector<std::uint32_t>{0});
}

TEST_CASE("kdtree cells: the same cell tree and answers with 1 and 2 threads") {
    const engine::Mesh mesh = engine::make_builtin_scene("builtin:cornell").mesh;
    auto rays = testing::random_rays_into(mesh.bounds, 3000, 5);
    const auto cam = testing::camera_rays(mesh.bounds, 40, 40);
    rays.insert(rays.end(), cam.begin(), cam.end());
    for (const accel::KdWalk walk : {accel::KdWalk::cells, accel::KdWalk::tight_cells}) {
    CAPTURE(accel::kd_walk_name(walk));
    accel::BuildConfig cfg;
    cfg.kd_blocks.walk = walk;
    std::vector<Hit> hits[2];
    accel::BinaryBvh bvh[2];
    for (int t = 0; t < 2; ++t) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(t + 1));
        const auto kd = accel::make_kdtree_accel(mesh.view(), cfg);
        REQUIRE(kd->walk() == walk);
        REQUIRE(kd->cell_paths() != nullptr);
        bvh[t] = accel::kd_cell_bvh(kd->tree(), walk == accel::KdWalk::tight_cells);
        for (const auto path : {accel::TracePath::single, accel::TracePath::packet})
            for (const auto q : {accel::Query::closest, accel::Query::any}) {
                std::vector<Hit> h(rays.size());
                accel::trace_parallel(*kd, rays, h, q, path, 64);
                hits[t].insert(hits[t].end(), h.begin(), h.end());
            }
    }
    REQUIRE(bvh[0].nodes.size() == bvh[1].nodes.size());
    CHECK(std::memcmp(bvh[0].nodes.data(), bvh[1].nodes.data(), bvh[0].nodes.size() * sizeof(accel::BvhBuildNode)) == 0);
    CHECK(bvh[0].prim_ids == bvh[1].prim_ids);
    REQUIRE(hits[0].size() == hits[1].size());
    CHECK(std::memcmp(hits[0].data(), hits[1].data(), hits[0].size() * sizeof(Hit)) == 0);
}
}
