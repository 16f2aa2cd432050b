// WideLayout<N> collapsed from binary BVHs: every finite triangle exactly once with its original
// vertices and id, NaN/invalid padding, empty unused child slots, child boxes that contain their
// subtrees, leaf limits (merged subtrees, chunked big leaves), recorded depth; deterministic.
#include "accel/bvh/bvh_build.h"
#include "accel/lbvh/lbvh_build.h"
#include "accel/wide/wide_layout.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"
#include "testing.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cstring>
#include <functional>
#include <initializer_list>

using namespace arbor;
using accel::Bounds;
using accel::Vec3f;

namespace {

/// A binary BVH builder on prim refs (bvh-median, bvh-sah, lbvh).
using RefsBuilder = accel::BinaryBvh (*)(const accel::PrimRefs&, const accel::BvhBuildConfig&);

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Checks the layout's invariants; returns the leaves' largest triangle count.
template <std::size_t N>
std::uint32_t check_layout(const accel::WideLayout<N>& L, const accel::TriangleView& v, std::uint32_t max_leaf) {
    std::size_t finite = 0;
    for (std::size_t t = 0; t < v.triangle_count(); ++t) finite += v.triangle_is_finite(t);
    if (finite == 0) {
        CHECK(L.empty());
        return 0;
    }
    REQUIRE(!L.empty());
    std::vector<int> seen(v.triangle_count(), 0), node_seen(L.nodes.size(), 0);
    std::vector<int> block_seen(L.blocks.size(), 0);
    std::uint32_t largest = 0, deepest = 0;
    std::size_t leaves = 0, bad_box = 0, bad_vertex = 0, bad_pad = 0;
    // Returns the bounds of what lies below (child, count).
    std::function<Bounds(std::uint32_t, std::uint32_t, std::uint32_t)> walk = [&](std::uint32_t child, std::uint32_t count,
                                                                                    std::uint32_t depth) {
        Bounds b;
        if (count != 0) {
            ++leaves;
            largest = std::max(largest, count);
            for (std::uint32_t blk = 0; blk < accel::wide_blocks<N>(count); ++blk) ++block_seen[child + blk];
            for (std::uint32_t s = 0; s < accel::wide_blocks<N>(count) * N; ++s) {
                const std::size_t slot = std::size_t(child) * N + s;
                const std::uint32_t id = L.prim(slot);
                if (s >= count) {
                    bad_pad += id != accel::invalid_prim || !std::isnan(L.vertex(slot, 0).x) || !std::isnan(L.vertex(slot, 2).z);
                    continue;
                }
                REQUIRE(id < v.triangle_count());
                ++seen[id];
                for (int k = 0; k < 3; ++k) {
                    const Vec3f a = L.vertex(slot, k), c = v.corner(id, k);
                    bad_vertex += !(same_bits(a.x, c.x) && same_bits(a.y, c.y) && same_bits(a.z, c.z));
                    b.grow(c);
                }
            }
            return b;
        }
        REQUIRE(child < L.nodes.size());
        ++node_seen[child];
        deepest = std::max(deepest, depth);
        const accel::WideNode<N>& n = L.nodes[child];
        CHECK(n.children >= 1);
        CHECK(n.children <= N);
        for (std::size_t c = 0; c < N; ++c) {
            const Vec3f lo{n.boxes.b[0][0][c], n.boxes.b[0][1][c], n.boxes.b[0][2][c]};
            const Vec3f hi{n.boxes.b[1][0][c], n.boxes.b[1][1][c], n.boxes.b[1][2][c]};
            if (c >= n.children) {
                bad_pad += !(lo.x == INFINITY && lo.y == INFINITY && lo.z == INFINITY && hi.x == -INFINITY && hi.z == -INFINITY);
                continue;
            }
            const Bounds sub = walk(n.child[c], n.count[c], depth + 1);
            bad_box += !Bounds{lo, hi}.contains(sub);
            b.grow(sub);
        }
        return b;
    };
    walk(0, 0, 1);
    CHECK(bad_box == 0);
    CHECK(bad_vertex == 0);
    CHECK(bad_pad == 0);
    CHECK(deepest == L.depth);
    CHECK(leaves == L.leaves);
    CHECK(largest <= max_leaf);
    std::size_t twice = 0, missing = 0;
    for (std::size_t t = 0; t < v.triangle_count(); ++t) {
        if (v.triangle_is_finite(t)) missing += seen[t] == 0;
        else CHECK(seen[t] == 0);
        twice += seen[t] > 1;
    }
    CHECK(missing == 0);
    CHECK(twice == 0);
    for (int s : node_seen) CHECK(s == 1);
    for (int s : block_seen) CHECK(s == 1);
    return largest;
}

template <std::size_t N> void check_all_builders(const accel::TriangleView& v, accel::BvhBuildConfig cfg, accel::WideConfig wc) {
    const accel::PrimRefs refs = accel::make_prim_refs(v);
    for (const RefsBuilder build : std::initializer_list<RefsBuilder>{accel::build_bvh_median, accel::build_bvh_sah, accel::build_lbvh}) {
        const accel::BinaryBvh bvh = build(refs, cfg);
        const auto L = accel::make_wide_layout<N>(bvh, v, wc);
        const std::uint32_t limit = std::min(wc.max_leaf_triangles, std::max<std::uint32_t>(cfg.max_leaf_size, wc.merge_triangles ? wc.merge_triangles : N));
        check_layout<N>(L, v, limit);
    }
}

}  // namespace

TEST_CASE_TEMPLATE("wide layout: invariants for every builder, leaf sizes, merges and chunked leaves", W,
                   std::integral_constant<std::size_t, 4>, std::integral_constant<std::size_t, 8>,
                   std::integral_constant<std::size_t, 16>) {
    constexpr std::size_t N = W::value;
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.2f, 5);
    mesh.append(engine::make_torus({1.5f, 0.2f, -0.3f}, 1.0f, 0.25f, 24, 10));
    mesh.append(engine::make_box({-3, -1.2f, -3}, {3, -1.1f, 3}));
    for (const std::uint32_t leaf : {1u, 4u, 40u})
        for (const std::uint32_t merge : {0u, 1u, 8u, 32u})
            for (const std::uint32_t max_leaf : {3u, 65535u}) {
                accel::BvhBuildConfig cfg;
                cfg.max_leaf_size = leaf;
                accel::WideConfig wc;
                wc.merge_triangles = merge;
                wc.max_leaf_triangles = max_leaf;
                CAPTURE(leaf);
                CAPTURE(merge);
                CAPTURE(max_leaf);
                check_all_builders<N>(mesh.view(), cfg, wc);
            }
}

TEST_CASE("wide layout: tiny, empty and non-finite scenes") {
    engine::Mesh one;
    one.add_vertex({0, 0, 0}), one.add_vertex({1, 0, 0}), one.add_vertex({0, 1, 0});
    one.indices = {0, 1, 2};
    one.compute_bounds();
    check_all_builders<16>(one.view(), {}, {});
    check_all_builders<4>(one.view(), {}, {});
    engine::Mesh nan = one;
    nan.x[1] = NAN;
    check_all_builders<8>(nan.view(), {}, {});
    const engine::Mesh empty;
    check_all_builders<8>(empty.view(), {}, {});
    // All centroids equal: 300 copies of one triangle.
    engine::Mesh same = one;
    for (int i = 0; i < 299; ++i) same.indices.insert(same.indices.end(), {0, 1, 2});
    check_all_builders<16>(same.view(), {}, {});
}

TEST_CASE("wide layout: a shared model at every width, identical with 1 and 2 threads") {
    const auto paths = testing::model_paths();
    if (paths.empty()) return;
    engine::Warnings w;
    const engine::Mesh mesh = engine::load_obj(testing::shared_scenes_dir() + "/models/cow.obj", w);
    const accel::PrimRefs refs = accel::make_prim_refs(mesh.view());
    const accel::BinaryBvh bvh = accel::build_bvh_sah(refs, {});
    const auto L16 = accel::make_wide_layout<16>(bvh, mesh.view());
    check_layout<16>(L16, mesh.view(), 16);
    check_layout<8>(accel::make_wide_layout<8>(bvh, mesh.view()), mesh.view(), 8);
    check_layout<4>(accel::make_wide_layout<4>(bvh, mesh.view()), mesh.view(), 4);
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    const auto serial = accel::make_wide_layout<16>(bvh, mesh.view());
    REQUIRE(serial.nodes.size() == L16.nodes.size());
    REQUIRE(serial.blocks.size() == L16.blocks.size());
    CHECK(std::memcmp(serial.nodes.data(), L16.nodes.data(), L16.nodes.size() * sizeof(L16.nodes[0])) == 0);
    CHECK(std::memcmp(serial.blocks.data(), L16.blocks.data(), L16.blocks.size() * sizeof(L16.blocks[0])) == 0);
}

namespace {

/// The SAH cost the collapse minimizes, of a wide layout: node boxes' areas x node cost plus leaf
/// boxes' areas x blocks x block cost (a node's box is the union of its children's).
template <std::size_t N> double wide_sah(const accel::WideLayout<N>& L, const accel::WideConfig& wc) {
    double cost = 0.0;
    std::function<void(std::uint32_t)> node = [&](std::uint32_t i) {
        const accel::WideNode<N>& n = L.nodes[i];
        Bounds all;
        for (std::size_t c = 0; c < n.children; ++c) {
            const Bounds b{{n.boxes.b[0][0][c], n.boxes.b[0][1][c], n.boxes.b[0][2][c]},
                           {n.boxes.b[1][0][c], n.boxes.b[1][1][c], n.boxes.b[1][2][c]}};
            all.grow(b);
            if (n.count[c]) cost += b.area() * wc.block_cost * accel::wide_blocks<N>(n.count[c]);
            else node(n.child[c]);
        }
        cost += all.area() * wc.node_cost;
    };
    node(0);
    return cost;
}

/// The same cost of the binary tree taken as it is (every interior node a 2-wide node): one of the
/// collapses the optimum was chosen from.
double binary_sah(const accel::BinaryBvh& bvh, std::size_t n, const accel::WideConfig& wc) {
    double cost = 0.0;
    for (const accel::BvhBuildNode& node : bvh.nodes)
        cost += node.is_leaf() ? node.box.area() * wc.block_cost * double((node.count + n - 1) / n) : node.box.area() * wc.node_cost;
    return cost;
}

}  // namespace

TEST_CASE_TEMPLATE("wide layout: the SAH collapse costs no more than the binary tree, merged leaves no more than unmerged", W,
                   std::integral_constant<std::size_t, 4>, std::integral_constant<std::size_t, 16>) {
    constexpr std::size_t N = W::value;
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.2f, 5);
    mesh.append(engine::make_torus({1.5f, 0.2f, -0.3f}, 1.0f, 0.25f, 24, 10));
    const accel::PrimRefs refs = accel::make_prim_refs(mesh.view());
    for (const RefsBuilder build : std::initializer_list<RefsBuilder>{accel::build_bvh_median, accel::build_bvh_sah, accel::build_lbvh}) {
        const accel::BinaryBvh bvh = build(refs, {});
        for (const float block_cost : {1.0f, 3.0f, 8.0f}) {
            accel::WideConfig wc;
            wc.block_cost = block_cost;
            wc.merge_triangles = 1;  // only binary leaves: the binary tree itself is a candidate
            const auto L = accel::make_wide_layout<N>(bvh, mesh.view(), wc);
            CAPTURE(block_cost);
            const double wide = wide_sah(L, wc), binary = binary_sah(bvh, N, wc);
            CHECK(wide <= binary * (1.0 + 1e-5));
            // Real collapsing happened: the optimum skips binary nodes (fewer, fuller nodes).
            std::size_t interior = 0;
            for (const auto& node : bvh.nodes) interior += !node.is_leaf();
            CHECK(L.nodes.size() * 2 < interior);
            // Merging allowed: never costlier than without.
            wc.merge_triangles = 0;
            CHECK(wide_sah(accel::make_wide_layout<N>(bvh, mesh.view(), wc), wc) <= wide * (1.0 + 1e-5));
        }
    }
}
