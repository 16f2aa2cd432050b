#pragma once
/// Small scenes for the renderer tests (a few hundred triangles, so brute force is quick even
/// under the sanitizers), a one-call render with brute force, and one on every path of bvh-sah.
#include "accel/factory/make_accel.h"
#include "accel/interface/accel.h"
#include "accel/structures/brute_accel.h"
#include "engine/procedural.h"
#include "engine/renderer.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cstring>
#include <memory>

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

/// A structure traced on one path, whatever its callers ask (the renderer asks for `best` and the
/// path policy would choose per ray kind): the way to run the renderer on each path.
class PinnedPath final : public accel::Accel {
public:
    PinnedPath(std::unique_ptr<accel::Accel> inner, accel::TracePath path)
        : Accel(inner->kind()), inner_(std::move(inner)), path_(path) {
        stats_ = inner_->stats();
        offer_ = inner_->offer();
    }

private:
    void run(std::span<const accel::Ray> rays, std::span<accel::Hit> hits, accel::Query query, accel::TracePath,
             accel::TraceCounters* counters) const override {
        inner_->trace(rays, hits, {query, counters ? accel::TracePath::scalar : path_, {}, {}, counters});
    }

public:
    void trace_all(std::span<const accel::Ray> rays, accel::HitSink& sink) const override { inner_->trace_all(rays, sink); }
    void closest_points(std::span<const accel::Vec3f> points, float max_distance,
                        std::span<accel::PointHit> out) const override {
        inner_->closest_points(points, max_distance, out);
    }

private:
    std::unique_ptr<accel::Accel> inner_;
    accel::TracePath path_;
};

/// Renders `s` with brute force and with bvh-sah pinned to its packet path and to its single-ray
/// path (every ray kind), and requires the three images to be identical bit for bit: every path
/// returns the same closest-hit record (t, prim, u, v; one tie rule, accel/core/hit_record.h), and
/// of an any-hit answer (shadow and AO rays) the renderer reads only whether it hit. Returns brute
/// force's image, so whatever a test asserts of it holds for the fast paths' images too.
inline engine::Image render_all_paths(const engine::Scene& s, const engine::RenderSettings& set, int threads = 2,
                                      engine::RenderStats* stats = nullptr) {
    const engine::Image ref = render_brute(s, set, threads, stats);
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    for (const accel::TracePath path : {accel::TracePath::packet, accel::TracePath::single}) {
        const PinnedPath bvh(accel::make_accel(accel::AccelKind::bvh_sah, s.mesh.view()), path);
        const engine::Image img = engine::render(s, bvh, set);
        CAPTURE(accel::to_string(path));
        REQUIRE(img.names == ref.names);
        std::size_t differing = 0;
        for (std::size_t c = 0; c < ref.planes.size(); ++c)
            for (std::size_t i = 0; i < ref.planes[c].size(); ++i)
                differing += std::memcmp(&ref.planes[c][i], &img.planes[c][i], sizeof(float)) != 0;
        CHECK(differing == 0);
    }
    return ref;
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
