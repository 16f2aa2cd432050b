// The renderer: finite, non-negative pixels; the same image with 1 and 2 threads; the planned
// ray counts (no shadow rays without lights).
#include "accel/brute_accel.h"
#include "engine/procedural.h"
#include "engine/renderer.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>

using namespace arbor;

namespace {
engine::Scene small_scene() {
    engine::Scene s;
    s.mesh = engine::make_ground(0.0f, 0.0f, 0.0f, 3.0f);
    s.mesh.append(engine::make_icosphere({0, 1, 0}, 0.8f, 2));
    s.camera.eye = {0, 1.5f, 4};
    s.camera.look_at = {0, 0.8f, 0};
    s.lights.push_back({{2, 4, 2}, {20, 20, 20}});
    return s;
}
engine::Image render_with(int threads, const engine::Scene& s, engine::RenderStats* st = nullptr) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    accel::BruteAccel brute(s.mesh.view());
    engine::RenderSettings set;
    set.width = 40;
    set.height = 30;
    set.spp = 2;
    set.tile = 8;
    return engine::render(s, brute, set, st);
}
}  // namespace

TEST_CASE("render: finite, non-negative, and identical with 1 and 2 threads") {
    const auto s = small_scene();
    const auto a = render_with(1, s), b = render_with(2, s);
    for (std::size_t c = 0; c < 3; ++c) {
        CHECK(a.planes[c] == b.planes[c]);
        for (float v : a.planes[c]) {
            CHECK(std::isfinite(v));
            CHECK(v >= 0.0f);
        }
    }
}

TEST_CASE("render: no lights means no shadow rays") {
    auto s = small_scene();
    engine::RenderStats with, without;
    render_with(2, s, &with);
    s.lights.clear();
    render_with(2, s, &without);
    CHECK(with.primary == 40 * 30 * 2);
    CHECK(with.shadow > 0);
    CHECK(without.primary == with.primary);
    CHECK(without.shadow == 0);
}
