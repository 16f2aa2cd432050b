/// The path integrator: diffuse global illumination with next-event estimation and Russian
/// roulette (Kajiya 1986; NEE and roulette as in Arvo & Kirk 1990). At every hit: direct light
/// through shadow rays (point lights, and one point on an area light drawn by power), then one
/// continuation, a mirror or a cosine-weighted diffuse bounce, picked in proportion to the
/// lobes' mean reflectance. Emission is counted where a camera or mirror ray lands on an
/// emitter; after a diffuse bounce it is not, since next-event estimation already counted it.
/// Misses see the background (an environment that is never sampled directly, so always counted).
#include "engine/integrator.h"

#include "engine/shading.h"

namespace arbor::engine {

namespace {

using simd::dot;

float mean(const Vec3f& c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }

class PathIntegrator final : public Integrator {
public:
    void render_tile(const RenderContext& ctx, Tracer& tracer, TileFilm& film) const override {
        std::vector<accel::Ray> rays, mirror_rays, diffuse_rays;
        std::vector<accel::Hit> hits;
        std::vector<PathState> paths, mirror_paths, diffuse_paths;
        ShadowBatch shadows;
        const int spp = ctx.settings.spp, pass = samples_per_pass(film.tile, spp);
        for (int s0 = 0; s0 < spp; s0 += pass) {
            camera_batch(ctx, film.tile, s0, std::min(spp, s0 + pass), rays, paths);
            std::size_t mirror_count = 0;  // rays[0, mirror_count) are mirror rays, the rest diffuse
            for (int depth = 0; !rays.empty(); ++depth) {
                hits.resize(rays.size());
                const std::span<const accel::Ray> all(rays);
                const std::span<accel::Hit> all_hits(hits);
                if (depth == 0) {
                    tracer.closest(all, all_hits, RenderRayKind::primary);
                } else {
                    tracer.closest(all.first(mirror_count), all_hits.first(mirror_count), RenderRayKind::mirror);
                    tracer.closest(all.subspan(mirror_count), all_hits.subspan(mirror_count), RenderRayKind::diffuse);
                }
                shadows.clear();
                mirror_rays.clear(), diffuse_rays.clear(), mirror_paths.clear(), diffuse_paths.clear();
                for (std::size_t i = 0; i < rays.size(); ++i)
                    shade(ctx, depth, rays[i], hits[i], paths[i], film, shadows, mirror_rays, mirror_paths,
                          diffuse_rays, diffuse_paths);
                shadows.resolve(tracer, film);
                mirror_count = mirror_rays.size();
                rays.assign(mirror_rays.begin(), mirror_rays.end());
                rays.insert(rays.end(), diffuse_rays.begin(), diffuse_rays.end());
                paths.assign(mirror_paths.begin(), mirror_paths.end());
                paths.insert(paths.end(), diffuse_paths.begin(), diffuse_paths.end());
            }
        }
    }

private:
    static void shade(const RenderContext& ctx, int depth, const accel::Ray& ray, const accel::Hit& hit,
                      PathState& path, TileFilm& film, ShadowBatch& shadows, std::vector<accel::Ray>& mirror_rays,
                      std::vector<PathState>& mirror_paths, std::vector<accel::Ray>& diffuse_rays,
                      std::vector<PathState>& diffuse_paths) {
        const RenderPlan& plan = ctx.plan;
        if (!hit.is_hit()) {
            // With the sky sampled by shadow rays (next-event estimation), a diffuse bounce that
            // escapes was already counted there.
            if (plan.background && (path.specular || !plan.sky_shadows))
                film.color[path.pixel] += path.throughput * ctx.scene.background;
            return;
        }
        const Surface s = surface_at(ctx, ray, hit);
        if (!s.valid) return;
        if (depth == 0) record_layers(ctx, film, path.pixel, hit, s);
        const Material& m = *s.material;
        if (plan.emission && path.specular) film.color[path.pixel] += path.throughput * m.emission;
        if (plan.shadows()) sample_direct_light(ctx, s, path.throughput, path, shadows);
        if (depth >= plan.depth) return;
        // Pick the continuation: mirror with probability p_mirror, diffuse otherwise.
        const float wm = plan.mirror ? mean(m.mirror) : 0.0f, wd = plan.diffuse ? mean(s.albedo) : 0.0f;
        if (!(wm + wd > 0.0f)) return;
        const float p_mirror = wm / (wm + wd);
        const bool mirror = path.rng.next() < p_mirror;
        PathState next;
        next.pixel = path.pixel;
        Vec3f dir;
        if (mirror) {
            next.throughput = path.throughput * m.mirror * (1.0f / p_mirror);
            dir = mirror_direction(s, ray.dir);
        } else {
            next.throughput = path.throughput * s.albedo * (1.0f / (1.0f - p_mirror));
            const float u1 = path.rng.next(), u2 = path.rng.next();
            dir = above_surface(cosine_hemisphere(s.shading, u1, u2), s.normal);
        }
        next.specular = mirror;
        // Russian roulette: survive with probability q, the throughput's largest component.
        if (depth + 1 >= ctx.settings.rr_depth) {
            const float q = std::min(0.95f, simd::max_component(next.throughput));
            if (!(path.rng.next() < q)) return;
            next.throughput = next.throughput * (1.0f / q);
        }
        next.rng = path.rng;  // after every draw of this vertex, so the next vertex gets fresh dimensions
        const accel::Ray r{s.origin, 0.0f, dir, std::numeric_limits<float>::infinity()};
        if (mirror) {
            mirror_rays.push_back(r);
            mirror_paths.push_back(next);
        } else {
            diffuse_rays.push_back(r);
            diffuse_paths.push_back(next);
        }
    }
};

}  // namespace

std::unique_ptr<Integrator> make_path_integrator() { return std::make_unique<PathIntegrator>(); }

}  // namespace arbor::engine
