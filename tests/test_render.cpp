// The renderer: finite, non-negative pixels for every integrator; the same image (all layers)
// with 1 and 2 threads; rays counted per kind follow the plan (no shadow rays without lights,
// no mirror rays without mirrors, no bounces when nothing emits).
#include "engine/plan.h"
#include "render_scenes.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace arbor;
using engine::IntegratorKind;
using engine::RenderRayKind;
using testing::render_brute;
using testing::small_scene;
using testing::tiny_settings;

namespace {
const IntegratorKind all_integrators[] = {IntegratorKind::primary, IntegratorKind::ao, IntegratorKind::direct,
                                          IntegratorKind::path};

/// small_scene with an emissive quad too, so that every ray kind appears.
engine::Scene full_scene() {
    auto s = small_scene();
    auto quad = engine::with_material(engine::make_ground(2.5f, 0.0f, 0.0f, 0.4f), testing::emitter(5.0f));
    s.mesh.append(quad);
    s.mesh.compute_bounds();
    return s;
}
}  // namespace

TEST_CASE("render: every integrator gives finite, non-negative pixels, identical with 1 and 2 threads") {
    const auto s = full_scene();
    for (IntegratorKind k : all_integrators) {
        CAPTURE(engine::to_string(k));
        auto set = tiny_settings(k);
        set.layers = engine::Layers{true, true, true};
        const auto a = render_brute(s, set, 1), b = render_brute(s, set, 2);
        REQUIRE(a.names == b.names);
        REQUIRE(a.names.size() == 10);
        for (std::size_t c = 0; c < a.planes.size(); ++c) {
            CHECK(a.planes[c] == b.planes[c]);
            if (a.names[c] == "Z" || a.names[c].rfind("N.", 0) == 0) continue;  // Z is +inf on misses; N is signed
            for (float v : a.planes[c]) {
                REQUIRE(std::isfinite(v));
                REQUIRE(v >= 0.0f);
            }
        }
    }
}

TEST_CASE("render: the seed selects independent streams, the same seed repeats the image") {
    const auto s = small_scene();
    auto set = tiny_settings(IntegratorKind::path);
    const auto a = render_brute(s, set), b = render_brute(s, set);
    set.seed = 99;
    const auto c = render_brute(s, set);
    CHECK(a.planes[0] == b.planes[0]);
    CHECK(a.planes[0] != c.planes[0]);
}

TEST_CASE("render: rays per kind follow the plan") {
    const int w = 24, h = 18, spp = 2;
    const std::uint64_t camera = std::uint64_t(w * h * spp);
    engine::RenderStats st;

    SUBCASE("primary traces camera rays only") {
        render_brute(full_scene(), tiny_settings(IntegratorKind::primary, w, h, spp), 2, &st);
        CHECK(st.count(RenderRayKind::primary) == camera);
        CHECK(st.total() == camera);
    }
    SUBCASE("ao traces ao_samples rays per camera hit") {
        auto set = tiny_settings(IntegratorKind::ao, w, h, spp);
        set.ao_samples = 3;
        render_brute(full_scene(), set, 2, &st);
        CHECK(st.count(RenderRayKind::primary) == camera);
        CHECK(st.count(RenderRayKind::ao) > 0);
        CHECK(st.count(RenderRayKind::ao) % 3 == 0);
        CHECK(st.count(RenderRayKind::ao) <= 3 * camera);
        CHECK(st.count(RenderRayKind::shadow) + st.count(RenderRayKind::mirror) + st.count(RenderRayKind::diffuse) == 0);
    }
    SUBCASE("direct with a light and a mirror traces shadow and mirror rays, no diffuse bounces") {
        render_brute(small_scene(), tiny_settings(IntegratorKind::direct, w, h, spp), 2, &st);
        CHECK(st.count(RenderRayKind::shadow) > 0);
        CHECK(st.count(RenderRayKind::mirror) > 0);
        CHECK(st.count(RenderRayKind::diffuse) == 0);
    }
    SUBCASE("a scene without lights traces no shadow rays") {
        auto s = small_scene();
        s.lights.clear();
        render_brute(s, tiny_settings(IntegratorKind::direct, w, h, spp), 2, &st);
        CHECK(st.count(RenderRayKind::primary) == camera);
        CHECK(st.count(RenderRayKind::shadow) == 0);
        CHECK(st.count(RenderRayKind::mirror) > 0);  // the mirror still shows the sky
        render_brute(s, tiny_settings(IntegratorKind::path, w, h, spp), 2, &st);
        CHECK(st.count(RenderRayKind::shadow) == 0);
        CHECK(st.count(RenderRayKind::diffuse) > 0);  // the sky lights the scene
    }
    SUBCASE("a scene without mirrors traces no mirror rays") {
        auto s = small_scene();
        for (auto& m : s.mesh.materials) m.mirror = {0, 0, 0};
        render_brute(s, tiny_settings(IntegratorKind::direct, w, h, spp), 2, &st);
        CHECK(st.count(RenderRayKind::mirror) == 0);
        CHECK(st.count(RenderRayKind::shadow) > 0);
        render_brute(s, tiny_settings(IntegratorKind::path, w, h, spp), 2, &st);
        CHECK(st.count(RenderRayKind::mirror) == 0);
    }
    SUBCASE("nothing emits: path traces camera rays only") {
        auto s = small_scene();
        s.lights.clear();
        s.background = {0, 0, 0};
        const auto img = render_brute(s, tiny_settings(IntegratorKind::path, w, h, spp), 2, &st);
        CHECK(st.total() == camera);
        for (float v : img.planes[0]) CHECK(v == 0.0f);
    }
    SUBCASE("--depth 0: no bounce of any kind") {
        auto set = tiny_settings(IntegratorKind::path, w, h, spp);
        set.max_depth = 0;
        render_brute(full_scene(), set, 2, &st);
        CHECK(st.count(RenderRayKind::mirror) + st.count(RenderRayKind::diffuse) == 0);
        CHECK(st.count(RenderRayKind::shadow) > 0);
    }
    SUBCASE("area lights alone: one NEE shadow ray per diffuse hit at most") {
        auto s = full_scene();
        s.lights.clear();
        render_brute(s, tiny_settings(IntegratorKind::direct, w, h, spp), 2, &st);
        CHECK(st.count(RenderRayKind::shadow) > 0);
        CHECK(st.count(RenderRayKind::shadow) <= st.count(RenderRayKind::primary) + st.count(RenderRayKind::mirror));
    }
}

TEST_CASE("render: layers are written only when asked, named as in the EXR convention") {
    const auto s = small_scene();
    auto set = tiny_settings(IntegratorKind::direct);
    CHECK(render_brute(s, set).names == std::vector<std::string>{"R", "G", "B"});
    set.layers = engine::Layers{true, false, true};
    CHECK(render_brute(s, set).names == std::vector<std::string>{"R", "G", "B", "Z", "A.R", "A.G", "A.B"});
    set = tiny_settings(IntegratorKind::primary);
    CHECK(render_brute(s, set).names ==
          std::vector<std::string>{"R", "G", "B", "Z", "N.X", "N.Y", "N.Z", "A.R", "A.G", "A.B"});
}
