#include "engine/integrator.h"

#include "engine/hit_geometry.h"
#include "engine/shading.h"

#include "accel/core/offset_ray.h"

#include <algorithm>
#include <numbers>

namespace arbor::engine {

using accel::Hit;
using accel::Ray;
using simd::dot;

TileFilm::TileFilm(const Tile& t, const Layers& layers) : tile(t), color(std::size_t(t.pixels()), Vec3f{0.0f}) {
    if (layers.depth) depth.assign(std::size_t(t.pixels()), std::numeric_limits<float>::infinity());
    if (layers.normal) normal.assign(std::size_t(t.pixels()), Vec3f{0.0f});
    if (layers.albedo) albedo.assign(std::size_t(t.pixels()), Vec3f{0.0f});
}

RenderContext::RenderContext(const Scene& s, const Camera& c, const LightSet& l, const RenderPlan& p,
                             const RenderSettings& set)
    : scene(s), camera(c), lights(l), plan(p), settings(set) {
    const Mesh& m = s.mesh;
    if (m.materials.empty()) single_ = &fallback_;
    else if (!p.material || m.material.empty()) single_ = &m.materials[m.material.empty() ? 0 : m.material[0]];
}

int samples_per_pass(const Tile& tile, int spp) { return std::clamp(4096 / std::max(1, tile.pixels()), 1, spp); }

void camera_batch(const RenderContext& ctx, const Tile& tile, int s0, int s1, std::vector<Ray>& rays,
                  std::vector<PathState>& paths) {
    rays.clear();
    paths.clear();
    const PixelStrata strata(ctx.settings.spp);
    const int image_width = ctx.settings.width;
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) {
            const auto local = std::uint32_t((y - tile.y0) * tile.width() + (x - tile.x0));
            const auto global = std::uint32_t(y * image_width + x);
            for (int s = s0; s < s1; ++s) {
                PathState p;
                p.pixel = local;
                p.rng = SampleStream(ctx.settings.seed, global, std::uint32_t(s));
                float jx = 0.5f, jy = 0.5f;
                if (ctx.settings.jitter) {
                    const float u = p.rng.next(), v = p.rng.next();
                    strata.position(s, u, v, jx, jy);
                }
                rays.push_back(ctx.camera.ray(float(x) + jx, float(y) + jy));
                paths.push_back(p);
            }
        }
}

namespace {

/// n carried by the inverse transpose of `a`'s 3x3 part (`inv` is a's inverse), renormalized.
Vec3f carry_normal(const accel::Affine& inv, const Vec3f& n) {
    Vec3f w;
    for (int r = 0; r < 3; ++r) w[r] = float(inv.at(0, r) * n.x + inv.at(1, r) * n.y + inv.at(2, r) * n.z);
    const float len = simd::length(w);
    return len > 0.0f && std::isfinite(len) ? w / len : n;
}

/// What a surface takes from its hit's geometry `g` and its triangle's material (`prim`: the
/// scene's triangle number); the shading normal starts as the geometric one.
void set_geometry(const RenderContext& ctx, const HitGeometry& g, std::uint32_t prim, Surface& s) {
    s.normal = s.shading = g.normal;
    s.position = g.position;
    s.scale = g.scale;
    s.material = &ctx.material(prim);
    s.albedo = s.material->diffuse;
}

/// The shading of an instance's hit: the corners carried to the world as flatten() carries them
/// (so position, geometric normal and offsets are the flattened scene's), the vertex attributes
/// read from the mesh in object space, where the geometric normal turned to the ray is A^T n
/// (its side is kept: dot(A^T n, A^-1 d) = dot(n, d)), and carried back by the inverse transpose.
Surface placed_surface(const RenderContext& ctx, const Ray& ray, const Hit& hit, const PlacedPrim& pp) {
    Surface s;
    const RenderPlan& plan = ctx.plan;
    const Mesh& mesh = ctx.scene.mesh;
    const accel::Affine& a = *pp.to_world;
    const accel::TriangleView tris = mesh.view();
    Vec3f obj[3], w[3];
    for (int k = 0; k < 3; ++k) {
        obj[k] = tris.corner(pp.prim, k);
        const auto p = a.point(obj[k].x, obj[k].y, obj[k].z);
        w[k] = {float(p[0]), float(p[1]), float(p[2])};
    }
    const HitGeometry g = hit_geometry(w[0], w[1], w[2], ray, hit, plan.position);
    if (!g.valid) return s;
    set_geometry(ctx, g, pp.prim, s);
    const Barycentrics b = barycentrics(hit.u, hit.v);
    Vec3f ng_obj{0.0f};
    if (plan.vertex_normals) {
        Vec3f t;
        for (int r = 0; r < 3; ++r)
            t[r] = float(a.at(0, r) * g.normal.x + a.at(1, r) * g.normal.y + a.at(2, r) * g.normal.z);
        const float len = simd::length(t);
        ng_obj = len > 0.0f && std::isfinite(len) ? t / len : g.normal;
        const accel::Affine inv = a.inverse();
        s.shading = carry_normal(inv, shading_normal(mesh, pp.prim, b, ng_obj));
        if (simd::dot(s.shading, g.normal) <= 0.0f) s.shading = g.normal;
    }
    if (plan.textures || plan.vertex_colors)
        s.albedo = albedo_at(mesh, *s.material, pp.prim, b, plan.textures, plan.vertex_colors);
    if (plan.position) {
        Vec3f from = g.position;
        if (plan.vertex_normals) {
            const Vec3f p_obj = obj[0] * b.b0 + obj[1] * b.b1 + obj[2] * b.b2;
            const Vec3f lifted = terminator_point(mesh, pp.prim, b, p_obj, ng_obj);
            if (lifted.x != p_obj.x || lifted.y != p_obj.y || lifted.z != p_obj.z) {
                const auto q = a.point(lifted.x, lifted.y, lifted.z);
                from = {float(q[0]), float(q[1]), float(q[2])};
            }
        }
        s.origin = accel::offset_ray_origin(from, g.normal, g.scale);
    }
    s.valid = true;
    return s;
}

}  // namespace

Surface surface_at(const RenderContext& ctx, const Ray& ray, const Hit& hit) {
    Surface s;
    const PlacedPrim pp = ctx.scene.placed.locate(hit.prim);
    if (pp.to_world) return placed_surface(ctx, ray, hit, pp);
    const RenderPlan& plan = ctx.plan;
    const Mesh& mesh = ctx.scene.mesh;
    const HitGeometry g = hit_geometry(mesh.view(), ray, hit, plan.position);
    if (!g.valid) return s;  // zero-area or overflowing: ignore the hit
    set_geometry(ctx, g, hit.prim, s);
    const Barycentrics b = barycentrics(hit.u, hit.v);
    if (plan.vertex_normals) s.shading = shading_normal(mesh, hit.prim, b, g.normal);
    if (plan.textures || plan.vertex_colors) s.albedo = albedo_at(mesh, *s.material, hit.prim, b, plan.textures, plan.vertex_colors);
    if (plan.position) {
        const Vec3f from = plan.vertex_normals ? terminator_point(mesh, hit.prim, b, g.position, g.normal) : g.position;
        s.origin = accel::offset_ray_origin(from, g.normal, g.scale);
    }
    s.valid = true;
    return s;
}

Vec3f mirror_direction(const Surface& s, const Vec3f& dir) {
    const Vec3f r = dir - s.shading * (2.0f * dot(dir, s.shading));
    return dot(r, s.normal) > 0.0f ? r : dir - s.normal * (2.0f * dot(dir, s.normal));
}

void record_layers(const RenderContext& ctx, TileFilm& film, std::uint32_t pixel, const Hit& hit, const Surface& s) {
    const Layers& l = ctx.plan.layers;
    // The camera's ray direction has a unit component along the view axis, so t is the
    // camera-space depth.
    if (l.depth) film.depth[pixel] = std::min(film.depth[pixel], hit.t);
    if (l.normal) film.normal[pixel] += s.shading;
    if (l.albedo) film.albedo[pixel] += s.albedo;
}

void ShadowBatch::resolve(Tracer& tracer, TileFilm& film) {
    hits.resize(rays.size());
    tracer.any(rays, hits, RenderRayKind::shadow);
    for (std::size_t i = 0; i < rays.size(); ++i)
        if (!hits[i].is_hit()) film.color[pixel[i]] += contribution[i];
}

void sample_direct_light(const RenderContext& ctx, const Surface& s, const Vec3f& weight, PathState& path,
                         ShadowBatch& shadows) {
    if (is_black(s.albedo)) return;
    const Vec3f f = s.albedo * weight * (1.0f / std::numbers::pi_v<float>);
    const Vec3f origin = s.origin;
    if (ctx.plan.point_shadows) {
        for (const PointLight& light : ctx.lights.points()) {
            const Vec3f to = light.position - origin;
            const float dn = dot(s.shading, to);
            if (!(dn > 0.0f)) continue;  // behind the surface: no shadow ray needed
            const float d2 = dot(to, to);
            shadows.add({origin, 0.0f, to, 1.0f}, path.pixel, f * light.intensity * (dn / (d2 * std::sqrt(d2))));
        }
    }
    if (ctx.plan.area_shadows) {
        const float u0 = path.rng.next(), u1 = path.rng.next(), u2 = path.rng.next();
        const AreaSample a = ctx.lights.sample_area(u0, u1, u2);
        // End the shadow ray just in front of the emitter, on the side of the receiver.
        const Vec3f nl = dot(a.normal, origin - a.point) > 0.0f ? a.normal : -a.normal;
        const Vec3f to = accel::offset_ray_origin(a.point, nl, a.scale) - origin;
        const float d2 = dot(to, to);
        const float d = std::sqrt(d2);
        const float cos_s = dot(s.shading, to) / d, cos_l = dot(nl, to) / -d;
        if (cos_s > 0.0f && cos_l > 0.0f && a.pdf_area > 0.0f && d2 > 0.0f)
            shadows.add({origin, 0.0f, to, 1.0f}, path.pixel, f * a.radiance * (cos_s * cos_l / (d2 * a.pdf_area)));
    }
    if (ctx.plan.sky_shadows) {
        // Cosine-weighted: the density cos/pi cancels the BRDF's 1/pi and the cosine, leaving
        // albedo x sky for every ray that escapes.
        const float u1 = path.rng.next(), u2 = path.rng.next();
        const Vec3f d = above_surface(cosine_hemisphere(s.shading, u1, u2), s.normal);
        shadows.add({origin, 0.0f, d, std::numeric_limits<float>::infinity()}, path.pixel, s.albedo * weight * ctx.scene.background);
    }
}

std::unique_ptr<Integrator> make_integrator(IntegratorKind kind) {
    switch (kind) {
    case IntegratorKind::primary: return make_primary_integrator();
    case IntegratorKind::ao: return make_ao_integrator();
    case IntegratorKind::direct: return make_direct_integrator();
    case IntegratorKind::path: return make_path_integrator();
    case IntegratorKind::cost: return make_cost_integrator();
    }
    return nullptr;
}

}  // namespace arbor::engine
