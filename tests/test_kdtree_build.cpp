// kd-tree builder: structure, the reference invariant against brute-force overlap tests, ropes
// against point queries, determinism across thread counts and FP modes, statistics.
#include "accel/factory/make_accel.h"
#include "accel/structures/kdtree_accel.h"
#include "accel/kdtree/kdtree_build.h"
#include "accel/kdtree/kdtree_clip.h"
#include "engine/procedural.h"
#include "kdtree_checks.h"
#include "testing.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>
#include <xmmintrin.h>

#include <cstring>
#include <stdexcept>
#include <random>

using namespace arbor;
using accel::Hit;
using accel::Ray;
using accel::Vec3f;
using accel::BuildConfig;
using accel::KdBuildConfig;
using accel::KdTree;

namespace {

void check_all(const engine::Mesh& mesh, const KdBuildConfig& cfg) {
    const KdTree tree = accel::build_kdtree(mesh.view(), cfg);
    CHECK(testing::check_kdtree_structure(tree, mesh.view()) == "");
    CHECK(testing::check_kdtree_refs(tree, mesh.view()) == "");
    CHECK(testing::check_kdtree_ropes(tree) == "");
    CHECK(tree.leaves.size() > 1);
}

bool same_tree(const KdTree& a, const KdTree& b) {
    const auto bytes_equal = [](const auto& x, const auto& y) {
        return x.size() == y.size() && (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0);
    };
    return bytes_equal(a.nodes, b.nodes) && bytes_equal(a.leaves, b.leaves) && bytes_equal(a.refs, b.refs) &&
           bytes_equal(a.tris, b.tris);
}

}  // namespace

TEST_CASE("kdtree build: invariants on small meshes, with and without perfect splits") {
    const engine::Mesh meshes[] = {
        engine::make_icosphere({0.1f, 0.2f, -0.3f}, 1.0f, 2, 0.1f, 3),
        engine::make_torus({0, 0, 0}, 1.0f, 0.3f, 16, 8),
        testing::random_soup(300, 0.3f, 9),
        testing::integer_grid(8),
        testing::integer_cubes(3),
    };
    for (const bool perfect : {true, false}) {
        KdBuildConfig cfg;
        cfg.perfect_splits = perfect;
        for (std::size_t i = 0; i < std::size(meshes); ++i) {
            CAPTURE(perfect);
            CAPTURE(i);
            check_all(meshes[i], cfg);
        }
    }
}

TEST_CASE("kdtree build: leaves stay within the depth limit 8 + 1.3 log2 N") {
    CHECK(accel::kd_depth_limit(1) == 0);
    CHECK(accel::kd_depth_limit(1024) == 21);
    CHECK(accel::kd_depth_limit(std::size_t(1) << 40) == accel::kd_max_depth);
    KdBuildConfig cfg;
    cfg.traversal_cost = 0.01f;  // splitting looks almost free: only the limit stops it
    const engine::Mesh mesh = testing::random_soup(500, 0.2f, 4);
    const KdTree tree = accel::build_kdtree(mesh.view(), cfg);
    const auto st = accel::kd_tree_stats(tree);
    CHECK(tree.depth_limit == accel::kd_depth_limit(500));
    CHECK(st.max_depth == tree.depth_limit);
    CHECK(testing::check_kdtree_structure(tree, mesh.view()) == "");
    CHECK(testing::check_kdtree_ropes(tree) == "");
}

TEST_CASE("kdtree build: perfect-split clipping is conservative and exact about misses") {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int clipped = 0;
    for (int it = 0; it < 2000; ++it) {
        const Vec3f a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)};
        accel::Bounds box;
        box.grow(Vec3f{u(rng) * 0.5f, u(rng) * 0.5f, u(rng) * 0.5f});
        box.grow(Vec3f{u(rng) * 0.5f, u(rng) * 0.5f, u(rng) * 0.5f});
        const int axis = it % 3;
        accel::Bounds tb;
        for (const Vec3f& p : {a, b, c}) tb.grow(p);
        const accel::Bounds r = accel::clip_triangle_bounds(a, b, c, tb, box, axis);
        // Points of the triangle inside the box must be inside r.
        std::uniform_real_distribution<float> w(0.0f, 1.0f);
        for (int s = 0; s < 200; ++s) {
            float x = w(rng), y = w(rng);
            if (x + y > 1.0f) x = 1.0f - x, y = 1.0f - y;
            const Vec3f p = a + (b - a) * x + (c - a) * y;
            const bool inside = p.x >= box.lo.x && p.x <= box.hi.x && p.y >= box.lo.y && p.y <= box.hi.y &&
                                p.z >= box.lo.z && p.z <= box.hi.z;
            if (!inside) continue;
            REQUIRE_FALSE(r.empty());
            // p itself is rounded; allow its rounding.
            for (int k = 0; k < 3; ++k) {
                CHECK(p[k] >= r.lo[k] - 1e-6f);
                CHECK(p[k] <= r.hi[k] + 1e-6f);
            }
        }
        CHECK((r.empty() || box.contains(r)));
        CHECK((r.empty() || tb.contains(r)));
        clipped += !r.empty() && (r.hi - r.lo).x < (tb.hi - tb.lo).x;
        if (r.empty()) CHECK_FALSE(testing::triangle_meets_open_box(a, b, c, box));
    }
    CHECK(clipped > 100);  // clipping does tighten bounds
    // A flat triangle keeps its exact plane coordinate when clipped.
    const Vec3f a{0.1f, 0.3f, 0.7f}, b{0.9f, 0.35f, 0.7f}, c{0.4f, 0.95f, 0.7f};
    accel::Bounds tb;
    for (const Vec3f& p : {a, b, c}) tb.grow(p);
    accel::Bounds box{{0.0f, 0.0f, 0.0f}, {0.5f, 0.5f, 1.0f}};
    const accel::Bounds r = accel::clip_triangle_bounds(a, b, c, tb, box, 0);
    CHECK(r.lo.z == 0.7f);
    CHECK(r.hi.z == 0.7f);
    CHECK(r.hi.x <= 0.5f);
}

TEST_CASE("kdtree build: deterministic with 1 and 2 threads") {
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 4, 0.2f, 11);
    mesh.append(testing::random_soup(2000, 0.1f, 2));
    KdBuildConfig cfg;
    cfg.parallel_threshold = 64;  // many parallel splits on a small mesh
    KdTree one, two;
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
        one = accel::build_kdtree(mesh.view(), cfg);
    }
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
        two = accel::build_kdtree(mesh.view(), cfg);
    }
    CHECK(one.nodes.size() > 1000);
    CHECK(same_tree(one, two));
    // And the layout does not depend on where the build went parallel.
    cfg.parallel_threshold = 1u << 30;
    CHECK(same_tree(one, accel::build_kdtree(mesh.view(), cfg)));
}

TEST_CASE("kdtree build: FTZ/DAZ mode of the caller does not change the tree") {
    // Coordinates in the denormal range: DAZ would read them as 0 if the builder did not guard.
    engine::Mesh mesh = testing::random_soup(200, 0.3f, 21);
    for (auto* v : {&mesh.x, &mesh.y, &mesh.z})
        for (float& f : *v) f *= 1e-39f;
    mesh.compute_bounds();
    const KdTree plain = accel::build_kdtree(mesh.view());
    const unsigned saved = _mm_getcsr();
    _mm_setcsr(saved | 0x8040u);
    const KdTree flushed = accel::build_kdtree(mesh.view());
    const unsigned inside = _mm_getcsr();
    _mm_setcsr(saved);
    CHECK(inside == (saved | 0x8040u));  // the guard restored the caller's mode
    CHECK(plain.leaves.size() > 1);
    CHECK(same_tree(plain, flushed));
}

TEST_CASE("kdtree build: statistics") {
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 3);
    mesh.x[5] = std::numeric_limits<float>::quiet_NaN();
    const auto kd_built = accel::make_kdtree_accel(mesh.view());
    const accel::KdTreeAccel& kd = *kd_built;
    const accel::BuildStats& st = kd.stats();
    const KdTree& tree = kd.tree();
    std::size_t dropped = 0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) dropped += !mesh.view().triangle_is_finite(t);
    CHECK(dropped > 0);
    CHECK(st.dropped_nonfinite == dropped);
    CHECK(st.triangles == mesh.triangle_count());
    CHECK(tree.tris.size() == mesh.triangle_count() - dropped);
    CHECK(st.nodes == tree.nodes.size());
    CHECK(st.leaves == tree.leaves.size());
    CHECK(st.nodes == 2 * st.leaves - 1);
    CHECK(st.max_depth <= tree.depth_limit);
    CHECK(st.mean_leaf_depth > 1.0);
    CHECK(st.mean_leaf_depth <= st.max_depth);
    // The traversal structure plus the SIMD paths' layout: with the rope walks, the leaves' triangle
    // blocks (40 bytes per slot: 9 floats and an id); with the cell walks (the default: tight cells),
    // the cells' wide BVH.
    const std::size_t tree_bytes = tree.nodes.size() * 8 + tree.leaves.size() * 56 + tree.refs.size() * 4 + tree.tris.size() * 40;
    REQUIRE(kd.walk() == accel::KdWalk::tight_cells);
    REQUIRE(kd.cell_paths() != nullptr);
    CHECK(kd.cell_paths()->stats().memory_bytes > 0);
    CHECK(st.memory_bytes == tree_bytes + kd.cell_paths()->stats().memory_bytes);
    BuildConfig ropes;
    ropes.kd_blocks.walk = accel::KdWalk::ropes;
    const auto kd_ropes = accel::make_kdtree_accel(mesh.view(), ropes);
    CHECK(kd_ropes->walk() == accel::KdWalk::ropes);
    CHECK(kd_ropes->cell_paths() == nullptr);
    const std::size_t n = kd_ropes->simd_block_width();
    std::size_t slots = 0;
    for (const accel::KdLeaf& leaf : tree.leaves) slots += (leaf.count + n - 1) / n * n;
    CHECK(kd_ropes->stats().memory_bytes == tree_bytes + (tree.leaves.size() + 1) * 4 + slots * 40);
    CHECK(st.build_peak_bytes > 0);
    CHECK(st.build_ms >= 0.0);
    // SAH cost: a root-only tree costs K_I * N; a real tree costs much less.
    CHECK(st.sah_cost > 1.0);
    CHECK(st.sah_cost < 0.25 * double(tree.tris.size()));
    BuildConfig leaf_only;
    leaf_only.kd.traversal_cost = 1e9f;
    const auto root_leaf_built = accel::make_kdtree_accel(mesh.view(), leaf_only);
    const accel::KdTreeAccel& root_leaf = *root_leaf_built;
    CHECK(root_leaf.stats().leaves == 1);
    CHECK(root_leaf.stats().sah_cost == doctest::Approx(double(tree.tris.size())));
}

TEST_CASE("kdtree build: max_memory is honoured") {
    const engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 4);
    const KdBuildConfig cfg;
    const KdTree tree = accel::build_kdtree(mesh.view(), cfg);
    REQUIRE(tree.build_peak_bytes > 0);
    CHECK_THROWS_AS(accel::build_kdtree(mesh.view(), cfg, tree.build_peak_bytes / 2), std::length_error);
    CHECK(same_tree(tree, accel::build_kdtree(mesh.view(), cfg, tree.build_peak_bytes * 2)));
}
