// Rays lying in the plane of a flat mesh do no work: the box test's flat-slab rule
// (simd/ray_box.h, in_flat_slab) culls every box of the plane, and the kd-tree's walks do not
// start (flat_axis_can_hit), so the counted scalar path tests no triangle at all (it tested every
// triangle along each ray's line before). The answers are the stress suite's to check
// (stress/cases_in_plane.cpp); this file checks the work.
#include "accel/factory/make_accel.h"
#include "accel/interface/accel.h"
#include "engine/procedural.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace arbor;
using accel::Hit;
using accel::Ray;
using accel::Vec3f;

namespace {

engine::Mesh flat_grid(int cells, float height) {
    engine::Mesh m;
    for (int i = 0; i < cells; ++i)
        for (int j = 0; j < cells; ++j)
            m.append(engine::make_ground(height, float(i) + 0.5f, float(j) + 0.5f, 0.5f));
    m.compute_bounds();
    return m;
}

/// Rays from random points of the plane y = `height` over [0, cells]^2, in directions in it.
std::vector<Ray> in_plane_rays(int cells, float height, std::size_t n) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, float(cells)), angle(0.0f, 6.2831853f);
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < n; ++i) {
        const float a = angle(rng);
        rays.push_back({{u(rng), height, u(rng)}, 0.0f, {std::cos(a), 0.0f, std::sin(a)}, INFINITY});
    }
    return rays;
}

accel::TraceCounters counted(const accel::Accel& a, const std::vector<Ray>& rays, accel::Query q) {
    std::vector<Hit> hits(rays.size());
    accel::TraceCounters c;
    a.trace(rays, hits, {q, accel::TracePath::scalar, {}, {}, &c});
    for (const Hit& h : hits) CHECK(h.prim == accel::invalid_prim);
    return c;
}

}  // namespace

TEST_CASE("in-plane rays: no triangle tested on a flat mesh, by any structure, closest and any hit") {
    const int cells = 24;
    for (const float height : {0.0f, 0.3f, -1.7e4f}) {
        const engine::Mesh grid = flat_grid(cells, height);
        const auto rays = in_plane_rays(cells, height, 500);
        for (const auto kind : {accel::AccelKind::bvh_median, accel::AccelKind::bvh_sah, accel::AccelKind::lbvh,
                                accel::AccelKind::kdtree}) {
            accel::BuildConfig cfg;
            cfg.layouts = accel::Layouts::all;
            const auto a = accel::make_accel(kind, grid.view(), cfg);
            REQUIRE(a->offer().counts);
            for (const auto q : {accel::Query::closest, accel::Query::any}) {
                CAPTURE(accel::to_string(kind));
                CAPTURE(height);
                const accel::TraceCounters c = counted(*a, rays, q);
                CHECK(c.rays == rays.size());
                CHECK(c.triangles_tested == 0);
                CHECK(c.nodes_visited == 0);
            }
        }
    }
}

TEST_CASE("in-plane rays: a ray a hair off the plane, or tilted by a hair, is walked as before") {
    // The rule is exact: it culls only boxes of no thickness whose plane holds the origin, on an
    // axis the ray does not move along. Off the plane the box is missed by the slab test itself;
    // tilted, the ray crosses the plane and must find the triangle under its origin.
    const int cells = 8;
    const engine::Mesh grid = flat_grid(cells, 0.0f);
    const auto a = accel::make_accel(accel::AccelKind::bvh_sah, grid.view());
    const std::vector<Ray> rays{{{2.25f, 1e-3f, 3.75f}, 0.0f, {1.0f, -1e-3f, 0.0f}, INFINITY},   // crosses the plane at x = 3.25
                                {{2.25f, 1e-3f, 3.75f}, 0.0f, {1.0f, 0.0f, 0.0f}, INFINITY}};   // parallel, a hair above
    std::vector<Hit> hits(rays.size());
    a->trace(rays, hits, {accel::Query::closest, accel::TracePath::scalar});
    CHECK(hits[0].prim != accel::invalid_prim);
    CHECK(std::fabs(hits[0].t - 1.0f) < 1e-5f);
    CHECK(hits[1].prim == accel::invalid_prim);
}
