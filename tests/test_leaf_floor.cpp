// BvhBuildConfig::leaf_floor: a BVH built for the SIMD layouts only stops at ranges of the layout's
// width (one leaf block). Every builder keeps the floor exactly (no range of at most leaf_floor
// triangles is split, no leaf above the larger of floor and max_leaf_size), stays deterministic,
// and the SIMD-only structure still agrees with brute; --simd-leaf-floor 1 restores the fine tree.
#include "accel/dispatch/kernel_entries.h"
#include "accel/factory/make_accel.h"
#include "accel/structures/brute_accel.h"
#include "accel/structures/bvh_accel.h"
#include "accel/bvh/bvh_build.h"
#include "accel/lbvh/lbvh_build.h"
#include "accel/structures/wide_paths.h"
#include "engine/procedural.h"
#include "testing.h"

#include <tbb/global_control.h>

#include <doctest/doctest.h>

#include <cstring>

using namespace arbor;
using accel::BinaryBvh;
using accel::BuildConfig;

namespace {

/// Triangles in the subtree of node i.
std::uint32_t subtree_tris(const BinaryBvh& b, std::uint32_t i) {
    const auto& n = b.nodes[i];
    return n.is_leaf() ? n.count : subtree_tris(b, n.first) + subtree_tris(b, n.first + 1);
}

/// The smallest interior subtree (in triangles): it must exceed the floor.
std::uint32_t smallest_interior(const BinaryBvh& b) {
    std::uint32_t least = ~0u;
    for (std::uint32_t i = 0; i < b.nodes.size(); ++i)
        if (!b.nodes[i].is_leaf()) least = std::min(least, subtree_tris(b, i));
    return least;
}

}  // namespace

TEST_CASE("leaf floor: no range of at most leaf_floor triangles is split, by any builder, with 1 and 2 threads") {
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 4, 0.05f, 3);
    mesh.append(engine::make_torus({0.5f, 0, 0}, 1.0f, 0.3f, 32, 12));
    const auto v = mesh.view();
    const accel::PrimRefs refs = accel::make_prim_refs(v);
    const accel::BvhBuilder builders[] = {accel::build_bvh_median, accel::build_bvh_sah, accel::build_bvh_sah_sweep,
                                          accel::build_lbvh};
    const char* const names[] = {"median", "sah", "sweep", "lbvh"};
    for (int b = 0; b < 4; ++b) {
        for (std::uint32_t floor : {8u, 16u}) {
            CAPTURE(names[b]);
            CAPTURE(floor);
            accel::BvhBuildConfig cfg;
            cfg.leaf_floor = floor;
            cfg.parallel_threshold = 64;
            auto run = [&](int threads) {
                tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
                return builders[b](refs, cfg);
            };
            const BinaryBvh one = run(1), two = run(2);
            CHECK(accel::validate_bvh(one, v, floor) == "");
            CHECK(smallest_interior(one) > floor);
            REQUIRE(one.nodes.size() == two.nodes.size());
            CHECK(std::memcmp(one.nodes.data(), two.nodes.data(), one.nodes.size() * sizeof(accel::BvhBuildNode)) == 0);
            CHECK(one.prim_ids == two.prim_ids);
            const BinaryBvh fine = builders[b](refs, accel::BvhBuildConfig{});
            CHECK(smallest_interior(fine) <= floor);  // the floor changed the tree: the check above can fail
            CHECK(one.nodes.size() < fine.nodes.size());
        }
    }
}

TEST_CASE("leaf floor: SIMD-only BVH builds use the layout's width, agree with brute, and floor 1 turns it off") {
    const engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 4, 0.03f, 9);
    const auto v = mesh.view();
    const accel::BruteAccel brute(v);
    const auto rays = testing::random_rays_into(mesh.bounds, 800, 21);
    std::vector<accel::Hit> ref(rays.size());
    brute.trace(rays, ref, {accel::Query::closest, accel::TracePath::scalar});
    for (const auto kind : {accel::AccelKind::bvh_median, accel::AccelKind::bvh_sah, accel::AccelKind::lbvh}) {
        for (std::uint32_t width : {4u, 8u, 16u}) {
            if (!accel::wide_width_supported(width)) continue;
            CAPTURE(accel::to_string(kind));
            CAPTURE(width);
            BuildConfig cfg;
            cfg.layouts = accel::Layouts::simd;
            cfg.wide.width = width;
            const auto coarse = accel::make_accel(kind, v, cfg);
            cfg.bvh.simd_leaf_floor = 1;
            const auto fine = accel::make_accel(kind, v, cfg);
            BuildConfig all;
            const auto reference = accel::make_accel(kind, v, all);
            CHECK(fine->stats().sah_cost == reference->stats().sah_cost);  // the same binary tree
            // (bvh-median at width 4 = its leaf size: the same tree)
            CHECK(coarse->stats().nodes <= fine->stats().nodes);
            if (width > cfg.bvh.max_leaf_size) CHECK(coarse->stats().nodes < fine->stats().nodes);
            for (const auto path : {accel::TracePath::single, accel::TracePath::packet}) {
                std::vector<accel::Hit> got(rays.size()), any(rays.size());
                coarse->trace(rays, got, {accel::Query::closest, path});
                coarse->trace(rays, any, {accel::Query::any, path});
                CHECK(testing::count_disagreements(got, ref) == 0);
                CHECK(testing::count_occlusion_disagreements(any, ref) == 0);
            }
        }
    }
}
