// Scene::update_vertices on bad input: an unknown geom, another vertex count, a null array, a short
// stride, NaN and infinite coordinates, an unknown mode, a non-finite rays hint: Error
// (invalid_argument) naming the argument, and the scene answers as before. And the automatic
// decision itself (accel/select/refit_select.h) on figures given by hand.
#include "accel/select/refit_select.h"
#include "deform.h"
#include "engine/procedural.h"
#include "testing.h"

#include <arbor/arbor.h>

#include <doctest/doctest.h>

#include <bit>
#include <cmath>

using namespace arbor;

namespace {

/// The message of the Error(invalid_argument) that f throws ("" when it throws none or another).
template <class F> std::string invalid_argument_message(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.kind() == Error::Kind::invalid_argument ? e.what() : "";
    }
    return "";
}

}  // namespace

TEST_CASE("update_vertices: bad arguments throw invalid_argument naming them, and change nothing") {
    const engine::Mesh m = engine::make_icosphere({0, 0, 0}, 1.0f, 2, 0.0f, 1);
    const std::vector<float> p = testing::packed(m);
    Scene scene;
    scene.add_mesh(p, m.indices);
    scene.build({"bvh-sah", 0, 0});
    const std::vector<Ray> rays = [] {
        std::vector<Ray> r(64);
        for (std::size_t i = 0; i < r.size(); ++i) {
            r[i].org[0] = -3.0f, r[i].org[1] = 0.02f * float(i) - 0.6f, r[i].org[2] = 0.1f;
            r[i].dir[0] = 1.0f, r[i].dir[1] = 0.0f, r[i].dir[2] = 0.0f;
        }
        return r;
    }();
    const std::vector<Hit> before = scene.intersect(rays);
    const std::size_t v = m.vertex_count();
    std::vector<float> moved = p;
    for (float& c : moved) c *= 2.0f;

    CHECK(invalid_argument_message([&] { scene.update_vertices(1, moved); }).find("geom 1") != std::string::npos);
    CHECK(invalid_argument_message([&] { scene.update_vertices(0, std::vector<float>(moved.begin(), moved.end() - 3)); })
              .find("vertices: expected " + std::to_string(v)) != std::string::npos);
    CHECK(invalid_argument_message([&] { scene.update_vertices(0, std::vector<float>(moved.begin(), moved.end() - 1)); })
              .find("vertices must hold whole") != std::string::npos);
    CHECK(invalid_argument_message([&] { scene.update_vertices(0, nullptr, v, 12); }).find("vertices is null") != std::string::npos);
    CHECK(invalid_argument_message([&] { scene.update_vertices(0, moved.data(), v, 8); }).find("stride 8") != std::string::npos);
    for (const float bad : {NAN, INFINITY, -INFINITY}) {
        std::vector<float> q = moved;
        q[3 * 5 + 1] = bad;
        CHECK(invalid_argument_message([&] { scene.update_vertices(0, q); }).find("vertices[5] is not finite") != std::string::npos);
    }
    UpdateOptions fast;
    fast.mode = "fast";
    CHECK(invalid_argument_message([&] { scene.update_vertices(0, moved, fast); }).find("mode 'fast'") != std::string::npos);
    UpdateOptions nan_rays;
    nan_rays.rays = NAN;
    CHECK(invalid_argument_message([&] { scene.update_vertices(0, moved, nan_rays); }).find("rays") != std::string::npos);

    // Nothing changed: the same answers, no update recorded.
    const std::vector<Hit> after = scene.intersect(rays);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        CHECK(std::bit_cast<std::uint32_t>(after[i].t) == std::bit_cast<std::uint32_t>(before[i].t));
        CHECK(after[i].prim == before[i].prim);
    }
    CHECK(scene.update_action().empty());
    // And a good array still works afterwards.
    scene.update_vertices(0, moved);
    CHECK(scene.update_action() == "refit");
}

TEST_CASE("refit decision: rebuild exactly when the rays' extra time exceeds a rebuild") {
    accel::RefitJob job;
    job.refit.sah_cost = 1.5;
    job.refit.built_sah_cost = 1.0;
    job.rays_source = "given";
    job.ns_per_ray = 200.0;
    job.ns_source = "measured";
    job.rebuild_ms = 100.0;
    // 1M rays x 200 ns x 0.5 = 100 ms: a tie keeps the refit.
    job.rays = 1e6;
    accel::RefitChoice c = accel::choose_refit(job);
    CHECK_FALSE(c.rebuild);
    CHECK(c.extra_trace_ms == doctest::Approx(100.0));
    CHECK(c.reason.rfind("refit: SAH 1.5x the last build's; 1M rays (given) at 200 ns each (measured)", 0) == 0);
    job.rays = 2e6;
    c = accel::choose_refit(job);
    CHECK(c.rebuild);
    CHECK(c.reason.rfind("rebuild: ", 0) == 0);
    CHECK(c.reason.find("200 ms longer on the refitted tree, more than a rebuild (100 ms") != std::string::npos);
    // No rays: nothing to win.
    job.rays = 0.0;
    c = accel::choose_refit(job);
    CHECK_FALSE(c.rebuild);
    CHECK(c.reason.find("no rays expected") != std::string::npos);
    // A refit as good as the build: never a rebuild, however many rays.
    job.rays = 1e12;
    job.refit.sah_cost = 0.98;
    CHECK_FALSE(accel::choose_refit(job).rebuild);
    // Forced modes and structures without a refit.
    CHECK(accel::forced_reason(accel::UpdateMode::rebuild, nullptr) == "rebuild: asked for (mode rebuild)");
    CHECK(accel::forced_reason(accel::UpdateMode::refit, &job.refit) == "refit: asked for (mode refit); SAH 0.98x the last build's");
    CHECK(accel::unsupported_reason("why") == "rebuild: why");
    CHECK(accel::parse_update_mode("auto") == accel::UpdateMode::automatic);
    CHECK_FALSE(accel::parse_update_mode("Auto"));
}
