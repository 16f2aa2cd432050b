/// The primary integrator: camera rays only. Colour is the albedo lit by a light at the eye
/// (albedo x |cos| between the normal and the view ray); misses see the background. The first-hit
/// layers (depth, normal, albedo) are what this integrator is for.
#include "engine/integrator.h"

namespace arbor::engine {

namespace {

class PrimaryIntegrator final : public Integrator {
public:
    void render_tile(const RenderContext& ctx, Tracer& tracer, TileFilm& film) const override {
        std::vector<accel::Ray> rays;
        std::vector<accel::Hit> hits;
        std::vector<PathState> paths;
        const int spp = ctx.settings.spp, pass = samples_per_pass(film.tile, spp);
        for (int s0 = 0; s0 < spp; s0 += pass) {
            camera_batch(ctx, film.tile, s0, std::min(spp, s0 + pass), rays, paths);
            hits.resize(rays.size());
            tracer.closest(rays, hits, RenderRayKind::primary);
            for (std::size_t i = 0; i < rays.size(); ++i) {
                const std::uint32_t px = paths[i].pixel;
                if (!hits[i].is_hit()) {
                    if (ctx.plan.background) film.color[px] += ctx.scene.background;
                    continue;
                }
                const Surface s = surface_at(ctx, rays[i], hits[i]);
                if (!s.valid) continue;
                const float cos = std::fabs(simd::dot(s.shading, rays[i].dir)) / simd::length(rays[i].dir);
                film.color[px] += s.albedo * cos;
                record_layers(ctx, film, px, hits[i], s);
            }
        }
    }
};

}  // namespace

std::unique_ptr<Integrator> make_primary_integrator() { return std::make_unique<PrimaryIntegrator>(); }

}  // namespace arbor::engine
