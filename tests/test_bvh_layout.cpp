// Bvh2Layout and BvhAccel on hand-made binary trees (no builder involved): the conversion keeps
// every triangle with its original vertices and id, and the scalar traversal agrees with brute.
#include "accel/structures/brute_accel.h"
#include "accel/structures/bvh_accel.h"
#include "engine/procedural.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <functional>
#include <limits>

using namespace arbor;
using accel::BinaryBvh;
using accel::Hit;
using accel::Ray;

namespace {

/// A valid but naive tree: triangles in file order, ranges halved down to `leaf` triangles.
BinaryBvh index_split_tree(const accel::TriangleView& v, std::uint32_t leaf) {
    BinaryBvh bvh;
    for (std::uint32_t t = 0; t < v.triangle_count(); ++t)
        if (v.triangle_is_finite(t)) bvh.prim_ids.push_back(t);
        else ++bvh.dropped_nonfinite;
    if (bvh.prim_ids.empty()) return bvh;
    bvh.nodes.push_back({});
    std::function<void(std::uint32_t, std::uint32_t, std::uint32_t)> build = [&](std::uint32_t node, std::uint32_t b,
                                                                                 std::uint32_t e) {
        accel::Bounds box;
        for (std::uint32_t k = b; k < e; ++k) box.grow(v.triangle_bounds(bvh.prim_ids[k]));
        bvh.nodes[node].box = box;
        if (e - b <= leaf) {
            bvh.nodes[node].first = b, bvh.nodes[node].count = e - b;
            return;
        }
        const auto first = std::uint32_t(bvh.nodes.size());
        bvh.nodes[node].first = first, bvh.nodes[node].count = 0;
        bvh.nodes.resize(bvh.nodes.size() + 2);
        build(first, b, b + (e - b) / 2);
        build(first + 1, b + (e - b) / 2, e);
    };
    build(0, 0, std::uint32_t(bvh.prim_ids.size()));
    return bvh;
}

void check_against_brute(const engine::Mesh& mesh, const accel::BvhAccel& bvh, const std::vector<Ray>& rays) {
    accel::BruteAccel brute(mesh.view());
    std::vector<Hit> ref(rays.size()), got(rays.size()), ref_any(rays.size()), got_any(rays.size());
    brute.trace(rays, ref, {accel::Query::closest, accel::TracePath::scalar});
    bvh.trace(rays, got, {accel::Query::closest, accel::TracePath::scalar});
    brute.trace(rays, ref_any, {accel::Query::any, accel::TracePath::scalar});
    bvh.trace(rays, got_any, {accel::Query::any, accel::TracePath::scalar});
    CHECK(testing::count_disagreements(ref, got) == 0);
    CHECK(testing::count_occlusion_disagreements(got_any, ref) == 0);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (got[i].is_hit() && ref[i].is_hit() && got[i].prim == ref[i].prim) {
            CHECK(got[i].t == ref[i].t);  // same triangle, same inputs: bit-identical answer
            CHECK(got[i].u == ref[i].u);
        }
        if (got_any[i].is_hit()) CHECK(got_any[i].t >= got[i].t);
    }
}

}  // namespace

TEST_CASE("bvh layout: every triangle slot keeps its original vertices and id, sizes add up") {
    engine::Mesh mesh = engine::make_torus({0, 0, 0}, 1.0f, 0.3f, 20, 9);  // 360 triangles
    mesh.x[3] = std::numeric_limits<float>::quiet_NaN();
    const auto view = mesh.view();
    for (std::uint32_t leaf : {1u, 3u, 4u, 7u}) {
        CAPTURE(leaf);
        const BinaryBvh tree = index_split_tree(view, leaf);
        REQUIRE(accel::validate_bvh(tree, view, leaf).empty());
        const accel::Bvh2Layout layout = accel::make_bvh2_layout(tree, view);
        const auto tstats = accel::bvh_tree_stats(tree);
        CHECK(layout.nodes.size() == tstats.leaves - 1);
        CHECK(layout.max_depth == tstats.max_depth);
        std::size_t finite = 0;
        for (std::size_t t = 0; t < view.triangle_count(); ++t) finite += view.triangle_is_finite(t);
        CHECK(layout.blocks.size() == (finite + 3) / 4);  // leaves packed back to back
        CHECK(layout.prim_ids.size() == 4 * layout.blocks.size());
        for (std::size_t s = finite; s < layout.prim_ids.size(); ++s) CHECK(layout.prim_ids[s] == layout.prim_ids[finite - 1]);
        std::uint32_t next_slot = 0;  // depth-first, left child first: leaves come in slot order
        // Walk the layout: leaves reached, slots in range, vertices equal to the view's corners.
        std::vector<int> seen(view.triangle_count(), 0);
        std::vector<std::pair<std::uint32_t, std::uint32_t>> todo{{layout.root_child, layout.root_count}};
        std::uint32_t next_node = 0;
        while (!todo.empty()) {
            const auto [child, count] = todo.back();
            todo.pop_back();
            if (count == 0) {
                REQUIRE(child < layout.nodes.size());
                CHECK(child == next_node++);  // nodes in depth-first order
                for (int c = 1; c >= 0; --c) todo.push_back({layout.nodes[child].child[c], layout.nodes[child].count[c]});
                continue;
            }
            CHECK(child == next_slot);
            next_slot += count;
            for (std::uint32_t s = child; s < child + count; ++s) {
                const std::uint32_t t = layout.prim_ids[s];
                REQUIRE(t < view.triangle_count());
                ++seen[t];
                for (int k = 0; k < 3; ++k) {
                    CHECK(layout.vertex(s, k).x == view.corner(t, k).x);
                    CHECK(layout.vertex(s, k).z == view.corner(t, k).z);
                }
            }
        }
        for (std::size_t t = 0; t < view.triangle_count(); ++t) CHECK(seen[t] == (view.triangle_is_finite(t) ? 1 : 0));
    }
}

TEST_CASE("bvh accel: scalar traversal of a hand-made tree agrees with brute (closest and any hit)") {
    const engine::Mesh mesh = engine::make_icosphere({0.5f, -1.0f, 2.0f}, 1.5f, 3, 0.1f, 4);
    for (std::uint32_t leaf : {1u, 4u, 5u}) {
        CAPTURE(leaf);
        accel::BvhAccel bvh(accel::AccelKind::bvh_median, index_split_tree(mesh.view(), leaf), mesh.view(), {}, 0.0);
        CHECK(bvh.stats().nodes > 1);
        CHECK(bvh.stats().memory_bytes >= bvh.layout().nodes.size() * 64 + bvh.layout().blocks.size() * 144);
        check_against_brute(mesh, bvh, testing::random_rays_into(mesh.bounds, 1000, 1));
        check_against_brute(mesh, bvh, testing::random_rays_inside(mesh.bounds, 1000, 2));
        check_against_brute(mesh, bvh, testing::camera_rays(mesh.bounds, 32, 30));
    }
}

TEST_CASE("bvh accel: a root that is a leaf, an empty scene, untraceable rays") {
    const engine::Mesh box = engine::make_box({-1, -1, -1}, {1, 1, 1});
    accel::BvhAccel small(accel::AccelKind::bvh_sah, index_split_tree(box.view(), 16), box.view(), {}, 0.0);
    CHECK(small.layout().root_count == 12);
    CHECK(small.layout().nodes.empty());
    check_against_brute(box, small, testing::random_rays_into(box.bounds, 500, 3));

    const engine::Mesh none;
    accel::BvhAccel empty(accel::AccelKind::bvh_sah, index_split_tree(none.view(), 4), none.view(), {}, 0.0);
    CHECK_FALSE(empty.trace_one({{0, 0, 0}, 0, {1, 0, 0}, INFINITY}, accel::Query::closest).is_hit());
    CHECK(empty.stats().nodes == 0);

    accel::BvhAccel bvh(accel::AccelKind::bvh_sah, index_split_tree(box.view(), 1), box.view(), {}, 0.0);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const std::vector<Ray> rays = {
        {{0, 0, 5}, 0, {0, 0, -1}, inf},   {{nan, 0, 5}, 0, {0, 0, -1}, inf}, {{0, 0, 5}, 0, {0, nan, -1}, inf},
        {{0, 0, 5}, nan, {0, 0, -1}, inf}, {{0, 0, 5}, 0, {0, 0, -1}, nan},   {{inf, 0, 5}, 0, {0, 0, -1}, inf},
        {{0, 0, 5}, 0, {0, 0, 0}, inf},    {{0, 0, 5}, 10, {0, 0, -1}, 1},
    };
    for (bool any : {false, true}) {
        CHECK(bvh.trace_one(rays[0], any ? accel::Query::any : accel::Query::closest).is_hit());
        for (std::size_t i = 1; i < rays.size(); ++i) {
            CAPTURE(i);
            const Hit h = bvh.trace_one(rays[i], any ? accel::Query::any : accel::Query::closest);
            CHECK_FALSE(h.is_hit());
            CHECK(std::isinf(h.t));
        }
    }
}

TEST_CASE("bvh accel: statistics mode gives the same answers and counts nodes and triangle tests") {
    const engine::Mesh box = engine::make_box({-1, -1, -1}, {1, 1, 1});
    auto rays = testing::random_rays_into(box.bounds, 300, 8);
    rays.push_back({{0, 0, 0}, 0.0f, {0, 0, 0}, INFINITY});  // untraceable: counted as a ray only
    // A root that is a leaf of all 12 triangles: every traceable ray enters it and tests all 12.
    accel::BvhAccel leaf(accel::AccelKind::bvh_sah, index_split_tree(box.view(), 16), box.view(), {}, 0.0);
    std::vector<Hit> counted(rays.size()), plain(rays.size());
    accel::TraceCounters c;
    REQUIRE(leaf.offer().counts);
    leaf.trace(rays, counted, {accel::Query::closest, accel::TracePath::scalar, {}, {}, &c});
    leaf.trace(rays, plain, {accel::Query::closest, accel::TracePath::scalar});
    CHECK(testing::count_disagreements(counted, plain) == 0);
    CHECK(c.rays == rays.size());
    CHECK(c.nodes_visited == rays.size() - 1);
    CHECK(c.triangles_tested == 12 * (rays.size() - 1));

    const engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 3);
    accel::BvhAccel tree(accel::AccelKind::bvh_sah, index_split_tree(mesh.view(), 2), mesh.view(), {}, 0.0);
    const auto many = testing::random_rays_into(mesh.bounds, 500, 9);
    std::vector<Hit> closest(many.size()), any(many.size()), ref(many.size());
    accel::TraceCounters cc, ca;
    tree.trace(many, closest, {accel::Query::closest, accel::TracePath::scalar, {}, {}, &cc});
    tree.trace(many, any, {accel::Query::any, accel::TracePath::scalar, {}, {}, &ca});
    tree.trace(many, ref, {accel::Query::closest, accel::TracePath::scalar});
    CHECK(testing::count_disagreements(closest, ref) == 0);
    CHECK(testing::count_occlusion_disagreements(any, ref) == 0);
    CHECK(cc.nodes_visited > many.size());                                  // the tree is walked
    CHECK(cc.triangles_tested < many.size() * mesh.triangle_count() / 10);  // and prunes
    CHECK(ca.triangles_tested <= cc.triangles_tested);
}
