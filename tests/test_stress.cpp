// The stiff-case suite (stress/) at its small sizes over every structure make_accel builds and
// every path it implements: no false miss, false hit or double hit. Then the oracle on cases
// with known answers, and the judge on answers broken on purpose: it must catch each defect.
#include "accel/structures/brute_accel.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"
#include "simd/ray_triangle.h"
#include "stress/run.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace arbor;
using namespace arbor::stress;
using accel::Hit;
using accel::Ray;
using accel::Vec3f;

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();

void check_cases(const std::vector<StressCase>& cases) {
    const auto kinds = buildable_kinds();
    REQUIRE(kinds.size() >= 4);  // brute and the three BVHs at least
    for (const auto& c : cases) {
        const PreparedCase p = prepare(c);
        for (accel::AccelKind kind : kinds)
            for (const StressRow& r : run_case(p, kind)) {
                CAPTURE(c.name);
                CAPTURE(accel::to_string(kind));
                CAPTURE(accel::to_string(r.path));
                CAPTURE(r.walk);
                for (const auto& e : r.tally.examples) MESSAGE(e);
                CHECK(r.tally.rays == c.rays.size());
                CHECK(r.tally.false_miss == 0);
                CHECK(r.tally.false_hit == 0);
                CHECK(r.tally.double_hit == 0);
                CHECK(r.problem == "");
            }
    }
}

std::vector<StressCase> family(void (*add)(std::vector<StressCase>&, Size)) {
    std::vector<StressCase> out;
    add(out, Size::small);
    return out;
}

const StressCase& find(const std::vector<StressCase>& cases, const std::string& name) {
    for (const auto& c : cases)
        if (c.name == name) return c;
    FAIL("no case " << name);
    throw 0;
}

std::vector<Hit> brute_closest(const StressCase& c) {
    const accel::BruteAccel brute(c.mesh.view());
    std::vector<Hit> h(c.rays.size());
    brute.trace(c.rays, h, {accel::Query::closest, accel::TracePath::scalar});
    return h;
}

}  // namespace

TEST_CASE("stress: closed meshes (watertightness) over every structure and path") { check_cases(family(add_closed_cases)); }
TEST_CASE("stress: integer grids, node-box faces, axis-parallel rays over every structure and path") {
    check_cases(family(add_grid_cases));
}
TEST_CASE("stress: far, tiny and surface-spawned rays over every structure and path") { check_cases(family(add_precision_cases)); }
TEST_CASE("stress: degenerate geometry over every structure and path") { check_cases(family(add_degenerate_cases)); }
TEST_CASE("stress: rays in the plane of flat meshes over every structure and path") { check_cases(family(add_in_plane_cases)); }
TEST_CASE("stress: non-finite and extreme rays over every structure and path") { check_cases(family(add_ray_cases)); }

TEST_CASE("stress: a closed shared model (spot) from inside never leaks") {
    const std::string dir = testing::shared_scenes_dir();
    engine::Warnings w;
    const engine::Mesh spot = engine::load_obj(dir + "/models/spot.obj", w);
    REQUIRE(is_closed(spot));
    std::vector<StressCase> cases{make_closed_model_case(spot, "spot", Size::small)};
    std::size_t must = 0;
    for (const auto& t : cases[0].tags) must += t.must_hit();
    CHECK(must > 500);
    check_cases(cases);
    // An open model is refused.
    const engine::Mesh teapot = engine::load_obj(dir + "/models/teapot.obj", w);
    CHECK_FALSE(is_closed(teapot));
    CHECK_THROWS_AS((void)make_closed_model_case(teapot, "teapot", Size::small), std::invalid_argument);
}

TEST_CASE("stress: the cases test what they claim") {
    const auto closed = family(add_closed_cases);
    for (const auto& c : closed) {
        std::size_t must = 0, cont = 0, hit = 0;
        const auto h = brute_closest(c);
        for (std::size_t i = 0; i < c.rays.size(); ++i) must += c.tags[i].must_hit(), cont += c.tags[i].continuation, hit += h[i].is_hit();
        CAPTURE(c.name);
        CHECK(must > 300);
        CHECK(cont == must);
        CHECK(hit >= must);
    }
    // Rays from (0,0,0) aim exactly at the sphere's vertices: o + 1*d is the vertex.
    const StressCase& sphere = find(closed, "watertight-sphere");
    CHECK(sphere.rays[0].org.x == 0.0f);
    CHECK(sphere.rays[0].dir.x == sphere.mesh.x[0]);

    // The integer grid traced along the axes has no band at all (the oracle decides exactly),
    // except where a range ends exactly on a surface.
    const auto grid = family(add_grid_cases);
    const StressCase& g = find(grid, "grid-axis");
    const PreparedCase p = prepare(g);
    std::size_t open_range = 0, banded = 0, certain = 0;
    for (std::size_t i = 0; i < g.rays.size(); ++i)
        if (g.rays[i].tnear == 0.0f && g.rays[i].tfar == inf) ++open_range, banded += p.answers[i].band, certain += p.answers[i].certain_hit();
    CHECK(open_range > 1000);
    CHECK(banded == 0);
    CHECK(certain > open_range / 2);

    const auto precision = family(add_precision_cases);
    for (const auto& c : precision) {
        CAPTURE(c.name);
        CHECK(c.rays.size() > 200);
        if (c.name.rfind("surface-", 0) == 0)
            for (const auto& t : c.tags) CHECK(t.source_prim != accel::invalid_prim);
    }
    const auto rays = family(add_ray_cases);
    for (const Ray& r : find(rays, "nonfinite-rays").rays) CHECK_FALSE(accel::ray_is_traceable(r));
    for (const Ray& r : find(rays, "extreme-rays").rays) CHECK(accel::ray_is_traceable(r));
    const auto degenerate = family(add_degenerate_cases);
    CHECK(find(degenerate, "nonfinite-vertices").expected_dropped > 10);
}

TEST_CASE("stress oracle: exact verdicts on exact input, the band on inexact input") {
    engine::Mesh m;
    m.add_vertex({0, 0, 0}), m.add_vertex({2, 0, 0}), m.add_vertex({0, 2, 0}), m.add_vertex({2, 2, 0});
    m.add_triangle(0, 1, 2), m.add_triangle(1, 3, 2);
    const Oracle o(m.view());
    // Interior, axis-parallel: a certain hit at t = 3 exactly.
    TriVerdict v = o.classify({{0.5f, 0.5f, 3.0f}, 0.0f, {0.0f, -0.0f, -1.0f}, inf}, 0);
    CHECK(v.kind == TriVerdict::hit);
    CHECK(v.t == 3.0);
    // Exactly through the shared edge, axis-parallel, from either side: an exact zero edge that
    // the tie rule gives to exactly one of the two triangles, the one the triangle test hits.
    for (const float z : {3.0f, -3.0f}) {
        const Ray edge{{1.0f, 1.0f, z}, 0.0f, {0, 0, -z}, inf};
        const bool h0 = o.classify(edge, 0).kind == TriVerdict::hit, h1 = o.classify(edge, 1).kind == TriVerdict::hit;
        CHECK(h0 != h1);
        CHECK(o.classify(edge, h0 ? 1 : 0).kind == TriVerdict::miss);
        const auto sh = simd::woop_shear(edge.dir);
        CHECK(simd::woop_test(edge.org, sh, 0, inf, {0, 0, 0}, {2, 0, 0}, {0, 2, 0}).hit == h0);
        CHECK(simd::woop_test(edge.org, sh, 0, inf, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}).hit == h1);
        CHECK(o.answer(edge).certain_hit());
        CHECK_FALSE(o.answer(edge).band);
    }
    // Through the shared edge obliquely: within float rounding of it, so in the band.
    const Ray oblique{{0.3f, 0.1f, 3.0f}, 0.0f, Vec3f{1, 1, 0} - Vec3f{0.3f, 0.1f, 3.0f}, inf};
    CHECK(o.classify(oblique, 0).kind == TriVerdict::unsure);
    CHECK(o.answer(oblique).band);
    // Clearly outside, and in the plane (edge-on, exactly): misses.
    CHECK(o.classify({{5, 5, 3}, 0, {0, 0, -1}, inf}, 0).kind == TriVerdict::miss);
    CHECK(o.classify({{-1, 0.5f, 0}, 0, {1, 0, 0}, inf}, 0).kind == TriVerdict::miss);
    // Range: tfar short of the plane misses; tfar exactly on it is within rounding (t = Tv/det).
    CHECK(o.classify({{0.5f, 0.5f, 3}, 0, {0, 0, -1}, 2.5f}, 0).kind == TriVerdict::miss);
    CHECK(o.classify({{0.5f, 0.5f, 3}, 0, {0, 0, -1}, 3.0f}, 0).kind != TriVerdict::miss);
    // Untraceable rays and unknown triangles miss.
    CHECK(o.classify({{0.5f, 0.5f, 3}, 0, {0, 0, 0}, inf}, 0).kind == TriVerdict::miss);
    CHECK(o.classify({{0.5f, 0.5f, 3}, 0, {0, 0, -1}, inf}, 7).kind == TriVerdict::miss);
    // Crossing counts of a closed box: 1 from inside, 2 through it, 0 beside it.
    const engine::Mesh box = engine::make_box({-1, -1, -1}, {1, 1, 1});
    const Oracle b(box.view());
    CHECK(b.crossings({{0.1f, 0.2f, 0.3f}, 0, {0.3f, 0.5f, 0.7f}, inf}) == 1);
    CHECK(b.crossings({{-5, 0.2f, 0.3f}, 0, {1, 0.01f, 0.02f}, inf}) == 2);
    CHECK(b.crossings({{-5, 3, 0.3f}, 0, {1, 0.01f, 0.02f}, inf}) == 0);
}

TEST_CASE("stress judge: catches leaks, invented hits, wrong t, self-intersections and second crossings") {
    // Closed sphere: brute's answers pass; dropping hits is caught as false misses.
    const auto closed = family(add_closed_cases);
    const StressCase& sphere = find(closed, "watertight-sphere");
    const PreparedCase ps = prepare(sphere);
    std::vector<Hit> h = brute_closest(sphere);
    CHECK(judge(sphere, *ps.oracle, ps.answers, h, {}).failures() == 0);
    std::size_t dropped = 0, invented = 0;
    for (std::size_t i = 0; i < h.size() && dropped < 5; ++i)
        if (h[i].is_hit() && !sphere.tags[i].continuation) h[i] = accel::miss_hit, ++dropped;
    // A continuation ray that hits again where nothing is: a double hit.
    for (std::size_t i = 0; i < h.size() && invented < 3; ++i)
        if (sphere.tags[i].continuation && !h[i].is_hit()) h[i] = {2.0f, 0, 0.3f, 0.3f}, ++invented;
    Tally t = judge(sphere, *ps.oracle, ps.answers, h, {});
    CHECK(t.false_miss == 5);
    CHECK(t.double_hit == 3);
    CHECK(t.false_hit == 0);
    CHECK(t.examples.size() == 4);

    // Camera rays through the far-away scene: an invented hit, a wrong t, a hit behind the first surface.
    const auto precision = family(add_precision_cases);
    const StressCase& scene = find(precision, "translate-0");
    const PreparedCase pp = prepare(scene);
    h = brute_closest(scene);
    REQUIRE(judge(scene, *pp.oracle, pp.answers, h, {}).failures() == 0);
    const accel::BruteAccel brute(scene.mesh.view());
    int fake_hit = 0, wrong_t = 0, behind = 0;
    for (std::size_t i = 0; i < h.size(); ++i) {
        const Ray& r = scene.rays[i];
        if (scene.tags[i].must_hit() || scene.tags[i].continuation) continue;
        if (!h[i].is_hit() && !pp.answers[i].band && fake_hit < 2) {
            h[i] = {1.0f, 0, 0.2f, 0.2f}, ++fake_hit;
        } else if (h[i].is_hit() && pp.answers[i].certain_hit() && !pp.answers[i].band) {
            Ray past = r;
            past.tnear = h[i].t * 1.01f;
            const Hit second = brute.trace_one(past, accel::Query::closest);
            if (second.is_hit() && behind < 2) h[i] = second, ++behind;
            else if (wrong_t < 2) h[i].t *= 1.01f, ++wrong_t;
        }
    }
    REQUIRE(fake_hit == 2);
    REQUIRE(behind == 2);
    REQUIRE(wrong_t == 2);
    t = judge(scene, *pp.oracle, pp.answers, h, {});
    CHECK(t.false_hit == 4);
    CHECK(t.false_miss == 2);

    // Secondary rays: reporting the triangle a ray leaves is a double hit, in both queries.
    const StressCase& surface = find(precision, "surface-1");
    const PreparedCase pf = prepare(surface);
    h = brute_closest(surface);
    std::vector<Hit> any = h;
    REQUIRE(judge(surface, *pf.oracle, pf.answers, h, any).failures() == 0);
    for (std::size_t i = 0; i < 4; ++i) h[i] = any[i] = {1e-3f, surface.tags[i].source_prim, 0.3f, 0.3f};
    t = judge(surface, *pf.oracle, pf.answers, h, any);
    CHECK(t.double_hit == 8);
    CHECK(t.false_hit + t.false_miss == 0);

    // Untraceable rays that hit: false hits.
    const auto rays = family(add_ray_cases);
    const StressCase& bad = find(rays, "nonfinite-rays");
    const PreparedCase pb = prepare(bad);
    std::vector<Hit> hb(bad.rays.size());
    hb[3] = {1.0f, 0, 0, 0};
    CHECK(judge(bad, *pb.oracle, pb.answers, hb, {}).false_hit == 1);
}
