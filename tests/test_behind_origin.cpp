// Rays that reach behind their origin (tnear < 0) on a scene with coplanar overlapping triangles
// (the oracle tests' shapes standing on their own ground quad, and a second, larger ground quad in
// the same plane): a hit behind the origin lowers tfar below zero, and a deferred child popped
// against it must get slab_test's room for negative exits (simd::slab_accept), as it had when it
// was pushed. With a plain `entry <= tfar` at the pop, bvh-sah's scalar path culled the leaf of the
// lower (or closer-rounded) coplanar triangle: 400 of 200,000 such rays disagreed with brute
// (343 ties answered with the higher prim, 57 a later t), 185 of the 100,000 below.
//
// What is left is the known band of the directed search (docs/robustness.md, "Beyond CI: the directed search", the first open class):
// the two coplanar triangles' watertight t differ by their rounding (about eps * L / |d|, L their
// distance from the origin), and a box whose exact entry lies between them may be culled. Measured
// 1 of 200,000 rays here; the bound below leaves room for that band, not for the bug.
#include "accel/factory/make_accel.h"
#include "accel/interface/accel.h"
#include "engine/mesh.h"
#include "engine/procedural.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace arbor;
using accel::Hit;
using accel::Ray;
using accel::Vec3f;

TEST_CASE("behind the origin: a deferred box popped against a negative tfar keeps slab_test's room (every structure and path against brute)") {
    engine::Mesh mesh = testing::procedural_shapes();
    const Vec3f c = mesh.bounds.center(), e = mesh.bounds.extent();
    mesh.append(engine::make_ground(mesh.bounds.lo.y, c.x, c.z, 2.0f * std::max(e.x, e.z)));
    mesh.compute_bounds();
    std::vector<Ray> rays = testing::random_rays_inside(mesh.bounds, 100000, 5);
    const float len = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
    for (Ray& r : rays) r.tnear = -len, r.tfar = len;
    std::vector<Hit> brute(rays.size());
    accel::make_accel(accel::AccelKind::brute, mesh.view())->trace(rays, brute, {accel::Query::closest, accel::TracePath::scalar});
    std::size_t behind = 0;
    for (const Hit& h : brute) behind += h.is_hit() && h.t < 0.0f;
    CHECK(behind > rays.size() / 4);
    for (const auto kind : {accel::AccelKind::bvh_median, accel::AccelKind::bvh_sah, accel::AccelKind::lbvh, accel::AccelKind::kdtree}) {
        const auto acc = accel::make_accel(kind, mesh.view());
        for (const auto path : {accel::TracePath::scalar, accel::TracePath::single, accel::TracePath::packet}) {
            std::vector<Hit> got(rays.size());
            acc->trace(rays, got, {accel::Query::closest, path});
            std::size_t differ = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) differ += std::memcmp(&got[i], &brute[i], sizeof(Hit)) != 0;
            CAPTURE(accel::to_string(kind));
            CAPTURE(accel::to_string(path));
            CHECK(differ <= 4);
        }
    }
}
