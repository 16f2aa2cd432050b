// --accel auto (accel/select/auto_select.h): the pick is the smallest predicted total among the
// structures this build has (up to the tie rule, tested on fixed predictions), the reason is one
// line, a tiny budget picks the cheapest build without calibrating the others and a huge budget
// the fastest tracer (by the selector's own predictions), calibration times every SIMD path and keeps the faster,
// subset calibration builds only the anchor whole until refine() builds the contenders, and the
// structure handed over traces correctly.
#include "accel/select/auto_select.h"
#include "accel/brute/brute_accel.h"
#include "engine/procedural.h"
#include "perf/scenes.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

using namespace arbor;

namespace {
bool sorted_by_total(const accel::AutoChoice& c) {
    return std::is_sorted(c.predictions.begin(), c.predictions.end(),
                          [](const auto& a, const auto& b) { return a.total_ms < b.total_ms; });
}
}  // namespace

TEST_CASE("auto: whole-scene calibration picks the smallest predicted total") {
    const engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 4, 0.2f, 3);  // 5120 triangles
    const auto view = mesh.view();
    accel::AutoSelector sel(view);
    const auto rays = testing::random_rays_into(mesh.bounds, 2000, 4);
    for (const double budget : {1e6, 1e12}) {
        const auto c = sel.choose(rays, false, budget);
        REQUIRE_FALSE(c.predictions.empty());
        CHECK(sorted_by_total(c));
        const auto& front = c.predictions.front();
        const auto chosen = std::find_if(c.predictions.begin(), c.predictions.end(),
                                         [&](const auto& p) { return p.kind == c.kind; });
        REQUIRE(chosen != c.predictions.end());
        CHECK(chosen->total_ms <= front.total_ms * (1.0 + accel::AutoConfig{}.tie));  // the front, or tied with it
        CHECK(c.kind != accel::AccelKind::automatic);
        CHECK(c.path != accel::TracePath::best);
        CHECK(c.reason.find('\n') == std::string::npos);
        CHECK(c.reason.rfind(std::string(accel::to_string(c.kind)) + ": " + std::string(accel::to_string(c.path)) + " path", 0) == 0);
        CHECK(c.reason.find("calibrated on all") != std::string::npos);
        for (const auto& p : c.predictions) {
            CHECK(p.built_whole);
            CHECK(p.build_ms >= 0.0);
            CHECK(p.ns_per_ray > 0.0);
            CHECK(p.kind != accel::AccelKind::brute);  // 5120 triangles: brute is no candidate
        }
        if (budget == 1e12) {  // tracing dominates: the fastest tracer is the front
            for (const auto& p : c.predictions) CHECK(front.ns_per_ray <= p.ns_per_ray);
        }
    }
    CHECK(sel.calibration_ms() > 0.0);
    // The pick was built on the whole scene: it is handed over once, and it answers like brute.
    const auto c = sel.choose({}, false, 1e6);
    auto built = sel.take_built(c.kind);
    REQUIRE(built);
    CHECK(built->kind() == c.kind);
    CHECK_FALSE(sel.take_built(c.kind));
    accel::BruteAccel brute(view);
    std::vector<accel::Hit> a(rays.size()), b(rays.size());
    built->trace(rays, a, {accel::Query::closest, accel::TracePath::best});
    brute.trace(rays, b, {accel::Query::closest, accel::TracePath::scalar});
    CHECK(testing::count_disagreements(a, b) == 0);
}

TEST_CASE("auto: calibration times each structure on its SIMD paths and keeps the faster one") {
    const engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 4, 0.2f, 3);
    const auto view = mesh.view();
    const auto coherent = testing::camera_rays(mesh.bounds, 64, 32);        // 2048 rays, one camera
    const auto incoherent = testing::random_rays_into(mesh.bounds, 2048, 7);  // scattered origins
    for (const auto* rays : {&coherent, &incoherent}) {
        accel::AutoSelector sel(view);
        const auto preds = sel.predict(*rays, false);
        for (const auto& p : preds) {
            INFO(accel::to_string(p.kind));
            auto built = sel.take_built(p.kind);
            REQUIRE(built);
            CHECK(built->offer().has(p.path));
            if (built->offer().has(accel::TracePath::single))  // a SIMD structure runs a SIMD path
                CHECK((p.path == accel::TracePath::packet || p.path == accel::TracePath::single));
            else
                CHECK(p.path == accel::choose_path(built->offer(), *rays, {}).path);
            CHECK(std::isfinite(p.ns_per_ray));
            CHECK(p.ns_per_ray > 0.0);
        }
    }
}

TEST_CASE("auto: a tiny budget picks the cheapest build without calibrating the others") {
    const auto scene = perf::replicated(20000);
    const auto view = scene.scene.mesh.view();
    accel::AutoSelector sel(view);
    const auto c = sel.choose({}, false, 1.0);  // one ray: the build is everything
    CHECK(c.kind == accel::AccelKind::lbvh);
    REQUIRE(c.predictions.size() == 1);
    CHECK(c.reason.find("tiny budget") != std::string::npos);
    CHECK(c.reason.find('\n') == std::string::npos);
    CHECK_FALSE(sel.take_built(accel::AccelKind::bvh_sah));  // never built
    CHECK_FALSE(sel.take_built(accel::AccelKind::kdtree));
    // A budget whose trace time is far above the build calibrates everything (no shortcut).
    CHECK(sel.choose_tiny({}, false, 1e12).predictions.empty());
    auto built = sel.take_built(accel::AccelKind::lbvh);
    REQUIRE(built);
    CHECK(built->kind() == accel::AccelKind::lbvh);
}

TEST_CASE("auto: pick on fixed predictions: smallest total, tie rule, tiny and huge budgets") {
    const engine::Mesh box = engine::make_box({0, 0, 0}, {1, 1, 1});
    accel::AutoSelector sel(box.view());
    using accel::AccelKind;
    auto pred = [](AccelKind k, double build_ms, double ns) {
        accel::AutoPrediction p;
        p.kind = k, p.build_ms = build_ms, p.ns_per_ray = ns, p.built_whole = true;
        return p;
    };
    // Clear answers: a budget of 0 rays picks the cheapest build, a huge one the fastest tracer.
    const std::vector<accel::AutoPrediction> clear{pred(AccelKind::kdtree, 500, 100), pred(AccelKind::lbvh, 20, 400),
                                                   pred(AccelKind::bvh_sah, 80, 200)};
    CHECK(sel.pick(clear, 0.0).kind == AccelKind::lbvh);
    CHECK(sel.pick(clear, 1e12).kind == AccelKind::kdtree);
    // 1e6 rays: kdtree 600 ms, lbvh 420, bvh-sah 280: no tie, the smallest total.
    const auto mid = sel.pick(clear, 1e6);
    CHECK(mid.kind == AccelKind::bvh_sah);
    CHECK(mid.predictions.front().kind == AccelKind::bvh_sah);
    CHECK(mid.predictions.front().total_ms == doctest::Approx(280.0));
    CHECK(mid.reason.find("tie") == std::string::npos);
    // Build-bound tie (totals 100 and 102 ms, builds 100 and 60): the cheaper build.
    const auto b = sel.pick({pred(AccelKind::kdtree, 100, 0.0), pred(AccelKind::lbvh, 60, 42e3)}, 1000.0);
    CHECK(b.kind == AccelKind::lbvh);
    CHECK(b.predictions.front().kind == AccelKind::kdtree);  // still sorted by total
    CHECK(b.reason.find("tie within 5% with kdtree: cheaper build") != std::string::npos);
    // Trace-bound tie (1e9 rays, 100 vs 103 ns): the robust tree, bvh-sah.
    const auto t = sel.pick({pred(AccelKind::lbvh, 1, 100), pred(AccelKind::bvh_sah, 5, 103)}, 1e9);
    CHECK(t.kind == AccelKind::bvh_sah);
    CHECK(t.reason.find("the robust tree") != std::string::npos);
    // Outside the tie (120 ns: 20% slower): the smallest total.
    CHECK(sel.pick({pred(AccelKind::lbvh, 1, 100), pred(AccelKind::bvh_sah, 5, 120)}, 1e9).kind == AccelKind::lbvh);
    CHECK_THROWS_AS(sel.pick({}, 1.0), std::invalid_argument);
}

TEST_CASE("auto: subset calibration builds only the anchor whole and extrapolates the others") {
    const auto scene = perf::replicated(20000);
    const auto view = scene.scene.mesh.view();
    accel::AutoConfig cfg;
    cfg.full_triangles = 2000;
    cfg.sample_rays = 500;
    accel::AutoSelector sel(view, cfg);
    const auto preds = sel.predict({}, true);
    const auto c = sel.pick(preds, 1e7);
    REQUIRE_FALSE(c.predictions.empty());
    CHECK(sorted_by_total(c));
    CHECK(c.reason.find("of 20k triangles") != std::string::npos);
    std::size_t whole = 0;
    for (const auto& p : preds) {
        whole += p.built_whole;
        CHECK(std::isfinite(p.build_ms));
        CHECK(p.build_ms > 0.0);
        CHECK(std::isfinite(p.ns_per_ray));
        CHECK(p.ns_per_ray > 0.0);
    }
    CHECK(whole == 1);  // the anchor (lbvh when available)
    // A small budget refines nothing (every build would cost more than 10% of the total) ...
    CHECK(sel.refine(preds, {}, true, 10.0).size() == preds.size());
    for (const auto& p : sel.refine(preds, {}, true, 10.0)) CHECK(p.built_whole == (p.kind == accel::AccelKind::lbvh));
    // ... a huge one builds every contender whole and times it there (margin opened to all).
    {
        accel::AutoConfig all = cfg;
        all.refine_margin = 1e9;
        accel::AutoSelector wide(view, all);
        const auto refined = wide.refine(wide.predict({}, true), {}, true, 1e12);
        for (const auto& p : refined) CHECK(p.built_whole);
        CHECK(wide.pick(refined, 1e12).reason.find("refined") != std::string::npos);
    }
    // A given sample longer than sample_rays is cut into runs of consecutive rays (any size works).
    const auto rays = testing::camera_rays(scene.scene.mesh.bounds, 64, 48);
    for (const std::size_t n : {std::size_t(1), std::size_t(100), std::size_t(600), rays.size()}) {
        const auto c2 = sel.choose(std::span(rays).first(n), false, 1e6);
        const std::size_t expect = n <= 500 ? n : 512;  // 2 runs of 256
        // (", N rays" after a pick; "; N rays" when the tiny-budget shortcut took lbvh, which a
        // loaded machine's slow build can make happen.)
        CAPTURE(c2.reason);
        CHECK(c2.reason.find(" " + std::to_string(expect) + " rays, ") != std::string::npos);
    }
}

TEST_CASE("auto: brute is a candidate for tiny scenes only") {
    const engine::Mesh box = engine::make_box({0, 0, 0}, {1, 1, 1});
    accel::AutoSelector sel(box.view());
    const auto c = sel.choose({}, false, 100.0);
    CHECK(std::any_of(c.predictions.begin(), c.predictions.end(),
                      [](const auto& p) { return p.kind == accel::AccelKind::brute; }));
    const auto rays = accel::rays_into_bounds(box.bounds, 64, 9);
    REQUIRE(rays.size() == 64);
    accel::BruteAccel brute(box.view());
    for (const auto& r : rays) CHECK(brute.trace_one(r, accel::Query::closest).is_hit());  // aimed into the box
}
