// engine/ray_views: held-out camera and light placements keep their promises — the same seed the
// same placement, the camera outside the bounding sphere looking at it (its rays hit the model),
// the light on the camera's side, a flat model still gets shadow rays from every view, and a
// builtin scene's own camera only moves a little.
#include "accel/structures/brute_accel.h"
#include "accel/interface/trace.h"
#include "engine/builtin_scenes.h"
#include "engine/procedural.h"
#include "engine/ray_gen.h"
#include "engine/ray_views.h"
#include "testing.h"

#include <doctest/doctest.h>

using namespace arbor;

namespace {

engine::RayGenScene seeded(const engine::Scene& s, std::uint64_t seed, bool own = false) {
    engine::RayGenScene g = engine::ray_gen_scene(s, own);
    engine::place_seeded_view(g, s, seed, own);
    return g;
}

std::size_t hits_of(const engine::RayGenScene& g, const std::vector<accel::Ray>& rays) {
    const accel::BruteAccel brute(g.tris);
    std::vector<accel::Hit> hits(rays.size());
    accel::trace_parallel(brute, rays, hits, accel::Query::closest);
    std::size_t n = 0;
    for (const accel::Hit& h : hits) n += h.is_hit();
    return n;
}

}  // namespace

TEST_CASE("ray_views: seeded cameras orbit outside the bounding sphere, aimed at the model, light on the camera's side") {
    const engine::Scene s = engine::scene_from_mesh(engine::make_icosphere({1, 2, 3}, 2.0f, 2), "ball");
    const engine::Sphere sph = engine::bounding_sphere(s.mesh.bounds);
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
        const engine::RayGenScene g = seeded(s, seed);
        REQUIRE(g.camera);
        const engine::RayGenScene again = seeded(s, seed);
        CHECK(g.camera->eye.x == again.camera->eye.x);
        CHECK(g.light.z == again.light.z);
        const float d = simd::length(g.camera->eye - sph.center) / sph.radius;
        CHECK(d >= 1.59f);
        CHECK(d <= 3.51f);
        const float l = simd::length(g.light - sph.center) / sph.radius;
        CHECK(l >= 1.49f);
        CHECK(l <= 4.01f);
        CHECK(simd::dot(g.light - sph.center, g.camera->eye - sph.center) >= 0.0f);
        CHECK(simd::length(g.camera->look_at - sph.center) <= 0.151f * sph.radius);
        // Most primary rays of a view land on a model that fills its bounding sphere.
        engine::RayGenConfig cfg;
        cfg.count = 1024;
        const auto rays = engine::generate_rays(g, cfg);
        CHECK(hits_of(g, rays) >= rays.size() / 2);
    }
    CHECK(seeded(s, 1).camera->eye.x != seeded(s, 2).camera->eye.x);
}

TEST_CASE("ray_views: a flat model gets shadow rays from every seeded view") {
    // A single quad: a light on the far side of its plane from the camera lights nothing in view.
    const engine::Scene s = engine::scene_from_mesh(engine::make_ground(0.0f, 0.0f, 0.0f, 1.0f), "quad");
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        const engine::RayGenScene g = seeded(s, seed);
        const float cam_side = g.camera->eye.y, light_side = g.light.y;
        CHECK_MESSAGE(cam_side * light_side > 0.0f, "seed " << seed);
    }
}

TEST_CASE("ray_views: a builtin scene's own camera moves by at most a tenth of its distance") {
    const engine::Scene s = engine::make_builtin_scene("builtin:default");
    const float dist = simd::length(s.camera.eye - s.camera.look_at);
    for (std::uint64_t seed = 1; seed <= 10; ++seed) {
        const engine::RayGenScene g = seeded(s, seed, true);
        CHECK(simd::length(g.camera->eye - s.camera.eye) <= 0.1001f * dist);
        CHECK(simd::length(g.camera->look_at - s.camera.look_at) <= 0.0501f * dist);
        CHECK(g.camera->vfov_degrees == s.camera.vfov_degrees);
    }
}
