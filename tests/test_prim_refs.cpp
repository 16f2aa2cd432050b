// PrimRefs, the build input of every BVH: boxes and centroids of finite triangles in order,
// non-finite triangles dropped and counted, the same result with 1 and 2 threads.
#include "accel/bvh/prim_refs.h"
#include "engine/procedural.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cfloat>
#include <cmath>
#include <limits>

using namespace arbor;
using accel::Vec3f;

namespace {

/// Many small icospheres in a row, so that the input spans several blocks of make_prim_refs.
engine::Mesh many_spheres(int count) {
    engine::Mesh m;
    for (int i = 0; i < count; ++i) m.append(engine::make_icosphere({float(i) * 3.0f, 0.0f, 0.0f}, 1.0f, 2));
    return m;
}

}  // namespace

TEST_CASE("prim_refs: boxes, centroids and ids of every finite triangle in triangle order") {
    engine::Mesh m = many_spheres(60);  // 60 * 320 = 19200 triangles: three blocks
    const float nan = std::numeric_limits<float>::quiet_NaN();
    // Vertex 0 is used by triangles of sphere 0 only; an infinite vertex in a later sphere too.
    m.x[0] = nan;
    m.z[m.vertex_count() - 1] = std::numeric_limits<float>::infinity();
    const auto view = m.view();
    const accel::PrimRefs refs = accel::make_prim_refs(view);

    std::size_t expected_dropped = 0;
    for (std::size_t t = 0; t < view.triangle_count(); ++t) expected_dropped += !view.triangle_is_finite(t);
    REQUIRE(expected_dropped > 0);
    CHECK(refs.triangles == view.triangle_count());
    CHECK(refs.dropped_nonfinite == expected_dropped);
    REQUIRE(refs.size() == view.triangle_count() - expected_dropped);

    accel::Bounds bounds, centroid_bounds;
    std::size_t k = 0;
    for (std::size_t t = 0; t < view.triangle_count(); ++t) {
        if (!view.triangle_is_finite(t)) continue;
        CAPTURE(t);
        REQUIRE(refs.prim_ids[k] == t);
        const accel::Bounds box = view.triangle_bounds(t);
        CHECK(refs.box(k).lo.x == box.lo.x);
        CHECK(refs.box(k).hi.y == box.hi.y);
        CHECK(refs.box(k).hi.z == box.hi.z);
        const Vec3f c = refs.centroid(k);
        CHECK(c.x == box.lo.x * 0.5f + box.hi.x * 0.5f);
        CHECK(c.z == box.lo.z * 0.5f + box.hi.z * 0.5f);
        bounds.grow(box);
        centroid_bounds.grow(c);
        ++k;
    }
    CHECK(refs.bounds.lo.x == bounds.lo.x);
    CHECK(refs.bounds.hi.x == bounds.hi.x);
    CHECK(refs.bounds.hi.z == bounds.hi.z);
    CHECK(refs.centroid_bounds.lo.y == centroid_bounds.lo.y);
    CHECK(refs.centroid_bounds.hi.x == centroid_bounds.hi.x);
    CHECK(refs.memory_bytes() == refs.size() * 40);
}

TEST_CASE("prim_refs: identical with 1 and 2 threads") {
    engine::Mesh m = many_spheres(40);
    for (std::size_t i = 5; i < m.vertex_count(); i += 997) m.y[i] = std::numeric_limits<float>::quiet_NaN();
    auto build = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        return accel::make_prim_refs(m.view());
    };
    const accel::PrimRefs a = build(1), b = build(2);
    CHECK(a.dropped_nonfinite > 0);
    CHECK(a.prim_ids == b.prim_ids);
    CHECK(a.lo_x == b.lo_x);
    CHECK(a.hi_z == b.hi_z);
    CHECK(a.cy == b.cy);
    CHECK(a.dropped_nonfinite == b.dropped_nonfinite);
}

TEST_CASE("prim_refs: empty, all non-finite, and coordinates near FLT_MAX") {
    engine::Mesh empty;
    const accel::PrimRefs e = accel::make_prim_refs(empty.view());
    CHECK(e.empty());
    CHECK(e.bounds.empty());
    CHECK(e.centroid_bounds.empty());

    engine::Mesh bad = engine::make_box({-1, -1, -1}, {1, 1, 1});
    for (float& v : bad.x) v = std::numeric_limits<float>::quiet_NaN();
    const accel::PrimRefs b = accel::make_prim_refs(bad.view());
    CHECK(b.empty());
    CHECK(b.dropped_nonfinite == 12);
    CHECK(b.centroid_bounds.empty());

    // A box whose corners sit at +-3e38: lo + hi of a face at +3e38 would overflow, lo/2 + hi/2 not.
    engine::Mesh big = engine::make_box({-3e38f, -3e38f, 3e38f}, {3e38f, 3e38f, FLT_MAX});
    const accel::PrimRefs r = accel::make_prim_refs(big.view());
    REQUIRE(r.size() == 12);
    for (std::size_t i = 0; i < r.size(); ++i) {
        CHECK(std::isfinite(r.cx[i]));
        CHECK(std::isfinite(r.cz[i]));
    }
    CHECK(r.centroid_bounds.hi.z <= FLT_MAX);
    CHECK(r.centroid_bounds.hi.z >= 3e38f);
}
