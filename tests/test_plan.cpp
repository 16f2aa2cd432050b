// The render plan: what each scene and integrator needs, and the reasons for what is left out.
#include "engine/plan.h"
#include "render_scenes.h"

#include <doctest/doctest.h>

using namespace arbor;
using engine::IntegratorKind;

namespace {
engine::RenderPlan plan_for(const engine::Scene& s, IntegratorKind k, int depth = -1) {
    engine::RenderSettings set;
    set.integrator = k;
    set.max_depth = depth;
    const engine::LightSet lights(s);
    return engine::make_plan(s, lights, set);
}
bool skipped(const engine::RenderPlan& p, const std::string& what) {
    for (const auto& k : p.skipped)
        if (k.find(what) != std::string::npos) return true;
    return false;
}
}  // namespace

TEST_CASE("plan: scene traits count only materials some triangle uses") {
    auto s = testing::small_scene();
    s.mesh.materials.push_back(testing::emitter(3.0f));  // present, but no triangle uses it
    const engine::LightSet lights(s);
    const auto t = engine::scene_traits(s, lights);
    CHECK(t.diffuse);
    CHECK(t.mirror);
    CHECK_FALSE(t.emissive);
    CHECK_FALSE(t.single_material);
    CHECK(t.point_lights == 1);
    CHECK(t.emitters == 0);
}

TEST_CASE("plan: direct on a lit scene with a mirror") {
    const auto p = plan_for(testing::small_scene(), IntegratorKind::direct);
    CHECK(p.point_shadows);
    CHECK_FALSE(p.area_shadows);
    CHECK(p.mirror);
    CHECK_FALSE(p.diffuse);
    CHECK(p.position);
    CHECK(p.material);
    CHECK(p.depth == 3);
    CHECK(skipped(p, "shadow rays to area lights (no emissive triangle)"));
    CHECK(skipped(p, "emission lookups"));
    const std::string line = p.line("bvh-sah");
    CHECK(line.find("structure bvh-sah") != std::string::npos);
    CHECK(line.find("shadow(point)") != std::string::npos);
    CHECK(line.find("mirror") != std::string::npos);
    CHECK(line.find('\n') == std::string::npos);
    CHECK(p.skipped_lines().find("skipped: emission lookups (no emissive material)\n") != std::string::npos);
}

TEST_CASE("plan: no lights, no mirrors, one material") {
    engine::Scene s;
    s.mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 1);
    s.background = {0, 0, 0};
    const auto p = plan_for(s, IntegratorKind::path);
    CHECK_FALSE(p.shadows());
    CHECK_FALSE(p.mirror);
    CHECK_FALSE(p.diffuse);
    CHECK_FALSE(p.position);
    CHECK_FALSE(p.material);
    CHECK(skipped(p, "shadow rays to point lights (the scene has no point light)"));
    CHECK(skipped(p, "mirror rays (no mirror material"));
    CHECK(skipped(p, "diffuse bounces (nothing emits light"));
    CHECK(skipped(p, "per-hit material lookup (every triangle uses one material)"));
    CHECK(skipped(p, "hit positions"));
    s.background = {1, 1, 1};
    const auto lit = plan_for(s, IntegratorKind::path);
    CHECK(lit.diffuse);
    CHECK(lit.position);
    CHECK(lit.depth == 8);
}

TEST_CASE("plan: primary and ao trace no light rays, layers default per integrator") {
    const auto s = testing::small_scene();
    const auto primary = plan_for(s, IntegratorKind::primary);
    CHECK_FALSE(primary.shadows());
    CHECK_FALSE(primary.mirror);
    CHECK_FALSE(primary.position);
    CHECK(primary.layers.depth);
    CHECK(primary.layers.normal);
    CHECK(primary.layers.albedo);
    const auto ao = plan_for(s, IntegratorKind::ao);
    CHECK(ao.ao);
    CHECK(ao.position);
    CHECK_FALSE(ao.material);  // AO reads no material unless the albedo layer is asked for
    CHECK_FALSE(ao.layers.any());
    CHECK(ao.ao_radius > 0.0f);
    CHECK(skipped(ao, "shadow, mirror and bounce rays"));
}

TEST_CASE("plan: --depth 0 skips mirrors and bounces, black diffuse skips shadow rays") {
    auto s = testing::small_scene();
    const auto p = plan_for(s, IntegratorKind::path, 0);
    CHECK_FALSE(p.mirror);
    CHECK_FALSE(p.diffuse);
    CHECK(p.point_shadows);
    CHECK(skipped(p, "mirror rays (--depth 0)"));
    for (auto& m : s.mesh.materials) m.diffuse = {0, 0, 0};
    const auto q = plan_for(s, IntegratorKind::direct);
    CHECK_FALSE(q.shadows());
    CHECK(skipped(q, "no diffuse surface to light"));
}
