// --accel auto (accel/auto_select.h): the pick is the smallest predicted total among the
// structures this build has, the reason is one line, a budget of 0 rays picks the cheapest
// build and a huge budget the fastest tracer (by the selector's own predictions), subset
// calibration builds only the anchor whole, and the structure handed over traces correctly.
#include "accel/auto_select.h"
#include "accel/brute_accel.h"
#include "engine/procedural.h"
#include "perf/scenes.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <algorithm>

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
    for (const double budget : {0.0, 1e6, 1e12}) {
        const auto c = sel.choose(rays, false, budget);
        REQUIRE_FALSE(c.predictions.empty());
        CHECK(sorted_by_total(c));
        CHECK(c.kind == c.predictions.front().kind);
        CHECK(c.kind != accel::AccelKind::automatic);
        CHECK(c.reason.find('\n') == std::string::npos);
        CHECK(c.reason.rfind(std::string(accel::to_string(c.kind)) + ":", 0) == 0);
        CHECK(c.reason.find("calibrated on all") != std::string::npos);
        for (const auto& p : c.predictions) {
            CHECK(p.built_whole);
            CHECK(p.build_ms >= 0.0);
            CHECK(p.ns_per_ray > 0.0);
            CHECK(p.kind != accel::AccelKind::brute);  // 5120 triangles: brute is no candidate
        }
        if (budget == 0.0) {  // nothing to trace: the cheapest build wins
            for (const auto& p : c.predictions) CHECK(c.predictions.front().build_ms <= p.build_ms);
        }
        if (budget == 1e12) {  // tracing dominates: the fastest tracer wins
            for (const auto& p : c.predictions) CHECK(c.predictions.front().ns_per_ray <= p.ns_per_ray);
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
    built->intersect(rays, a, accel::TracePath::best);
    brute.intersect(rays, b, accel::TracePath::scalar);
    CHECK(testing::count_disagreements(a, b) == 0);
}

TEST_CASE("auto: subset calibration builds only the anchor whole and extrapolates the others") {
    const auto scene = perf::replicated(20000);
    const auto view = scene.scene.mesh.view();
    accel::AutoConfig cfg;
    cfg.full_triangles = 2000;
    cfg.sample_rays = 500;
    accel::AutoSelector sel(view, cfg);
    const auto c = sel.choose({}, true, 1e7);
    REQUIRE_FALSE(c.predictions.empty());
    CHECK(sorted_by_total(c));
    CHECK(c.reason.find("of 20k triangles") != std::string::npos);
    std::size_t whole = 0;
    for (const auto& p : c.predictions) {
        whole += p.built_whole;
        CHECK(std::isfinite(p.build_ms));
        CHECK(p.build_ms > 0.0);
        CHECK(std::isfinite(p.ns_per_ray));
        CHECK(p.ns_per_ray > 0.0);
    }
    CHECK(whole == 1);  // the anchor (lbvh when available)
    // A given sample longer than sample_rays is cut into runs of consecutive rays (any size works).
    const auto rays = testing::camera_rays(scene.scene.mesh.bounds, 64, 48);
    for (const std::size_t n : {std::size_t(1), std::size_t(100), std::size_t(600), rays.size()}) {
        const auto c2 = sel.choose(std::span(rays).first(n), false, 1e6);
        const std::size_t expect = n <= 500 ? n : 512;  // 2 runs of 256
        CHECK(c2.reason.find(", " + std::to_string(expect) + " rays") != std::string::npos);
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
    for (const auto& r : rays) CHECK(brute.trace(r, false).is_hit());  // aimed into the box
}
