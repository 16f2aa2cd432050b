// BuildPrims, what the BVH builders work on: made straight from the triangles they are the same
// records (boxes, ids, order, bounds, counts) as made from PrimRefs, for any thread count, and every
// builder makes the same tree from either (make_accel uses the first, the PrimRefs entry points the
// second).
#include "accel/bvh/build_prims.h"
#include "accel/bvh/bvh_build.h"
#include "accel/lbvh/lbvh_build.h"
#include "engine/procedural.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cfloat>
#include <cstring>
#include <limits>

using namespace arbor;

namespace {

/// Small icospheres in a row (several blocks of the parallel pass), a NaN and an infinite vertex,
/// and a box with corners near +-FLT_MAX.
engine::Mesh awkward_mesh() {
    engine::Mesh m;
    for (int i = 0; i < 50; ++i) m.append(engine::make_icosphere({float(i) * 3.0f, float(i % 7), 0.0f}, 1.0f, 2));
    m.x[0] = std::numeric_limits<float>::quiet_NaN();
    m.z[m.vertex_count() / 2] = std::numeric_limits<float>::infinity();
    m.append(engine::make_box({-3e38f, -3e38f, 3e38f}, {3e38f, 3e38f, FLT_MAX}));
    return m;
}

bool same_bits(const accel::Bounds& a, const accel::Bounds& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void check_same(const accel::BuildPrims& a, const accel::BuildPrims& b) {
    CHECK(a.triangles == b.triangles);
    CHECK(a.dropped_nonfinite == b.dropped_nonfinite);
    CHECK(same_bits(a.bounds, b.bounds));
    CHECK(same_bits(a.centroid_bounds, b.centroid_bounds));
    REQUIRE(a.size() == b.size());
    CHECK(std::memcmp(a.prims.data(), b.prims.data(), a.size() * sizeof(accel::BuildPrim)) == 0);
}

void check_same(const accel::BinaryBvh& a, const accel::BinaryBvh& b) {
    CHECK(a.dropped_nonfinite == b.dropped_nonfinite);
    CHECK(a.prim_ids == b.prim_ids);
    REQUIRE(a.nodes.size() == b.nodes.size());
    CHECK(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(accel::BvhBuildNode)) == 0);
}

}  // namespace

TEST_CASE("build prims: straight from the triangles, the records of PrimRefs, with 1 and 2 threads") {
    const engine::Mesh m = awkward_mesh();
    const auto view = m.view();
    auto direct = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        return accel::make_build_prims(view);
    };
    const accel::BuildPrims from_refs = accel::make_build_prims(accel::make_prim_refs(view));
    REQUIRE(from_refs.dropped_nonfinite > 0);
    REQUIRE(from_refs.size() + from_refs.dropped_nonfinite == view.triangle_count());
    check_same(direct(2), from_refs);
    check_same(direct(1), from_refs);
    // The records themselves: each finite triangle once, in order, its box and its number.
    const accel::BuildPrims p = direct(2);
    std::size_t k = 0;
    for (std::size_t t = 0; t < view.triangle_count(); ++t) {
        if (!view.triangle_is_finite(t)) continue;
        REQUIRE(k < p.size());
        CHECK(p.prims[k].id == t);
        CHECK(same_bits(p.prims[k].box(), view.triangle_bounds(t)));
        ++k;
    }
    CHECK(k == p.size());
    CHECK(p.centroid_bounds.hi.z <= FLT_MAX);  // lo/2 + hi/2: no overflow near FLT_MAX

    engine::Mesh none;
    const accel::BuildPrims e = accel::make_build_prims(none.view());
    CHECK(e.empty());
    CHECK(e.bounds.empty());
}

TEST_CASE("build prims: bvh-median, bvh-sah and lbvh make the same tree from the triangles as from PrimRefs") {
    const engine::Mesh m = awkward_mesh();
    const auto view = m.view();
    accel::BvhBuildConfig cfg;
    for (std::uint32_t floor : {0u, 16u}) {
        CAPTURE(floor);
        cfg.leaf_floor = floor;
        const accel::PrimRefs refs = accel::make_prim_refs(view);
        check_same(accel::build_bvh_median(accel::make_build_prims(view), cfg), accel::build_bvh_median(refs, cfg));
        check_same(accel::build_bvh_sah(accel::make_build_prims(view), cfg), accel::build_bvh_sah(refs, cfg));
        check_same(accel::build_lbvh(accel::make_build_prims(view), cfg), accel::build_lbvh(refs, cfg));
    }
}
