#pragma once
/// Small scenes for the renderer tests (a few hundred triangles, so brute force is quick even
/// under the sanitizers) and a one-call render with brute force.
#include "accel/brute/brute_accel.h"
#include "engine/procedural.h"
#include "engine/renderer.h"

#include <tbb/global_control.h>

namespace arbor::testing {

inline engine::Material diffuse(float r, float g, float b) { return {"diffuse", {r, g, b}, {}, {}}; }
inline engine::Material mirror(float k) { return {"mirror", {0, 0, 0}, {k, k, k}, {}}; }
inline engine::Material emitter(float le) { return {"emitter", {0, 0, 0}, {}, {le, le, le}}; }

/// Ground plane, a sphere and a mirror box, one point light, a sky.
inline engine::Scene small_scene() {
    engine::Scene s;
    s.mesh = engine::with_material(engine::make_ground(0.0f, 0.0f, 0.0f, 3.0f), diffuse(0.7f, 0.7f, 0.7f));
    s.mesh.append(engine::with_material(engine::make_icosphere({-0.5f, 0.8f, 0}, 0.8f, 2), diffuse(0.8f, 0.2f, 0.1f)));
    s.mesh.append(engine::with_material(engine::make_box({0.6f, 0, -0.5f}, {1.4f, 0.8f, 0.3f}), mirror(0.9f)));
    s.mesh.compute_bounds();
    s.camera.eye = {0, 1.5f, 4};
    s.camera.look_at = {0, 0.8f, 0};
    s.lights.push_back({{2, 4, 2}, {20, 20, 20}});
    s.background = {0.3f, 0.4f, 0.5f};
    return s;
}

/// Renders with brute force on `threads` threads.
inline engine::Image render_brute(const engine::Scene& s, const engine::RenderSettings& set, int threads = 2,
                                  engine::RenderStats* stats = nullptr) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    const accel::BruteAccel brute(s.mesh.view());
    return engine::render(s, brute, set, stats);
}

inline engine::RenderSettings tiny_settings(engine::IntegratorKind k, int w = 24, int h = 18, int spp = 2) {
    engine::RenderSettings set;
    set.width = w;
    set.height = h;
    set.spp = spp;
    set.tile = 8;
    set.integrator = k;
    return set;
}

}  // namespace arbor::testing
