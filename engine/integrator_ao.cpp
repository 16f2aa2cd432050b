/// Ambient occlusion: the fraction of cosine-weighted directions above a hit that leave the
/// surface unblocked within a radius, estimated with `ao_samples` any-hit rays per camera sample.
/// Misses (the open sky) count as unoccluded. The sky is white, or the background when the user
/// gave one (--background): camera rays that miss see it, and each unoccluded AO ray adds its share.
#include "engine/integrator.h"
#include "engine/shading.h"

namespace arbor::engine {

namespace {

class AoIntegrator final : public Integrator {
public:
    void render_tile(const RenderContext& ctx, Tracer& tracer, TileFilm& film) const override {
        std::vector<accel::Ray> rays, ao_rays;
        std::vector<accel::Hit> hits, ao_hits;
        std::vector<PathState> paths;
        std::vector<std::uint32_t> owner;
        const RenderPlan& plan = ctx.plan;
        const Vec3f sky = ctx.scene.background_given ? ctx.scene.background : Vec3f{1.0f};
        const Vec3f weight = sky * (plan.ao ? 1.0f / float(plan.ao_samples) : 0.0f);
        const int spp = ctx.settings.spp, pass = samples_per_pass(film.tile, spp);
        for (int s0 = 0; s0 < spp; s0 += pass) {
            camera_batch(ctx, film.tile, s0, std::min(spp, s0 + pass), rays, paths);
            hits.resize(rays.size());
            tracer.closest(rays, hits, RenderRayKind::primary);
            ao_rays.clear();
            owner.clear();
            for (std::size_t i = 0; i < rays.size(); ++i) {
                const std::uint32_t px = paths[i].pixel;
                if (!hits[i].is_hit()) {
                    film.color[px] += sky;
                    continue;
                }
                const Surface s = surface_at(ctx, rays[i], hits[i]);
                if (!s.valid) continue;
                record_layers(ctx, film, px, hits[i], s);
                if (!plan.ao) {
                    film.color[px] += sky;
                    continue;
                }
                for (int k = 0; k < plan.ao_samples; ++k) {
                    const float u1 = paths[i].rng.next(), u2 = paths[i].rng.next();
                    const Vec3f d = above_surface(cosine_hemisphere(s.shading, u1, u2), s.normal);
                    ao_rays.push_back({s.origin, 0.0f, d, plan.ao_radius});
                    owner.push_back(px);
                }
            }
            ao_hits.resize(ao_rays.size());
            tracer.any(ao_rays, ao_hits, RenderRayKind::ao);
            for (std::size_t k = 0; k < ao_rays.size(); ++k)
                if (!ao_hits[k].is_hit()) film.color[owner[k]] += weight;
        }
    }
};

}  // namespace

std::unique_ptr<Integrator> make_ao_integrator() { return std::make_unique<AoIntegrator>(); }

}  // namespace arbor::engine
