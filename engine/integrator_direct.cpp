/// The direct integrator (the seed report's ray tracer, Whitted style): at every hit, emission,
/// direct light from point lights and area lights through shadow rays, and a perfect mirror
/// reflection up to `depth` bounces. Misses see the background. Deterministic splitting: a
/// material with both a diffuse and a mirror lobe gets both.
#include "engine/integrator.h"


namespace arbor::engine {

namespace {

using simd::dot;

class DirectIntegrator final : public Integrator {
public:
    void render_tile(const RenderContext& ctx, Tracer& tracer, TileFilm& film) const override {
        std::vector<accel::Ray> rays, next_rays;
        std::vector<accel::Hit> hits;
        std::vector<PathState> paths, next_paths;
        ShadowBatch shadows;
        const RenderPlan& plan = ctx.plan;
        const int spp = ctx.settings.spp, pass = samples_per_pass(film.tile, spp);
        for (int s0 = 0; s0 < spp; s0 += pass) {
            camera_batch(ctx, film.tile, s0, std::min(spp, s0 + pass), rays, paths);
            for (int depth = 0; !rays.empty(); ++depth) {
                hits.resize(rays.size());
                tracer.closest(rays, hits, depth == 0 ? RenderRayKind::primary : RenderRayKind::mirror);
                shadows.clear();
                next_rays.clear();
                next_paths.clear();
                for (std::size_t i = 0; i < rays.size(); ++i) {
                    PathState& path = paths[i];
                    if (!hits[i].is_hit()) {
                        if (plan.background) film.color[path.pixel] += path.throughput * ctx.scene.background;
                        continue;
                    }
                    const Surface s = surface_at(ctx, rays[i], hits[i]);
                    if (!s.valid) continue;
                    if (depth == 0) record_layers(ctx, film, path.pixel, hits[i], s);
                    const Material& m = *s.material;
                    if (plan.emission) film.color[path.pixel] += path.throughput * m.emission;
                    if (plan.shadows()) sample_direct_light(ctx, s, path.throughput, path, shadows);
                    if (plan.mirror && depth < plan.depth && !is_black(m.mirror)) {
                        next_rays.push_back({s.origin, 0.0f, mirror_direction(s, rays[i].dir), std::numeric_limits<float>::infinity()});
                        PathState next = path;
                        next.throughput = path.throughput * m.mirror;
                        next_paths.push_back(next);
                    }
                }
                shadows.resolve(tracer, film);
                std::swap(rays, next_rays);
                std::swap(paths, next_paths);
            }
        }
    }
};

}  // namespace

std::unique_ptr<Integrator> make_direct_integrator() { return std::make_unique<DirectIntegrator>(); }

}  // namespace arbor::engine
