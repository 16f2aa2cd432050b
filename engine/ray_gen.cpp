#include "engine/ray_gen.h"

#include "accel/core/offset_ray.h"
#include "accel/factory/make_accel.h"
#include "accel/interface/trace.h"
#include "accel/util/splitmix64.h"
#include "engine/error.h"
#include "engine/hit_geometry.h"
#include "engine/sampling.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace arbor::engine {

using accel::Hit;
using accel::Ray;

namespace {

constexpr std::array<std::pair<RayKind, std::string_view>, 4> kind_names{{
    {RayKind::primary, "primary"},
    {RayKind::shadow, "shadow"},
    {RayKind::diffuse, "diffuse"},
    {RayKind::random, "random"},
}};

/// Uniform in [0, 1) from 24 random bits of splitmix64 (accel/util/splitmix64.h) used as a
/// counter-based generator, so every ray's numbers depend only on (seed, stream, index), never on
/// the order or thread it is made in.
float u01(std::uint64_t seed, std::uint64_t stream, std::uint64_t index) {
    using accel::splitmix64;
    return accel::unit_float24(splitmix64(seed ^ splitmix64(stream ^ splitmix64(index))));
}

// Streams: one per purpose, pass and dimension.
constexpr std::uint64_t stream_jitter = 0x100, stream_diffuse = 0x200, stream_random = 0x300, stream_light = 0x400;

/// The light of cfg.shadow: a point, or a square whose ray i aims at its own point.
class ShadowLight {
public:
    ShadowLight(const RayGenScene& scene, const ShadowRecipe& recipe, std::uint64_t seed) : seed_(seed) {
        const Sphere s = bounding_sphere(scene.bounds);
        centre_ = scene.light;
        if (recipe.light_distance > 0.0f) {
            const Vec3f away = scene.light - s.center;
            const float len = simd::length(away);
            const Vec3f unit = len > 0.0f ? away * (1.0f / len) : Vec3f{0.0f, 1.0f, 0.0f};
            centre_ = s.center + unit * (recipe.light_distance * s.radius);
        }
        if (recipe.light_size > 0.0f) {
            const Vec3f ext = scene.bounds.extent();
            side_ = recipe.light_size * std::max(ext.x, std::max(ext.y, ext.z));
            Vec3f facing = s.center - centre_;
            const float len = simd::length(facing);
            facing = len > 0.0f ? facing * (1.0f / len) : Vec3f{0.0f, -1.0f, 0.0f};
            orthonormal_basis(facing, t_, b_);
        }
    }
    Vec3f point(std::uint64_t id) const {
        if (side_ == 0.0f) return centre_;
        const float a = u01(seed_, stream_light, id) - 0.5f, c = u01(seed_, stream_light + 1, id) - 0.5f;
        return centre_ + t_ * (a * side_) + b_ * (c * side_);
    }

private:
    std::uint64_t seed_;
    Vec3f centre_, t_{0.0f}, b_{0.0f};
    float side_ = 0.0f;
};

/// Pixels of a width x height image in the requested order, keeping the first `count` in row-major
/// numbering (the same set of pixels for both orders).
std::vector<std::uint32_t> pixel_order(int width, int height, std::size_t count, PixelOrder order, int tile) {
    std::vector<std::uint32_t> px;
    px.reserve(count);
    if (order == PixelOrder::rows) {
        for (std::size_t i = 0; i < count; ++i) px.push_back(std::uint32_t(i));
        return px;
    }
    tile = std::max(tile, 1);
    for (int ty = 0; ty < height; ty += tile)
        for (int tx = 0; tx < width; tx += tile)
            for (int y = ty; y < std::min(ty + tile, height); ++y)
                for (int x = tx; x < std::min(tx + tile, width); ++x) {
                    const std::size_t i = std::size_t(y) * std::size_t(width) + std::size_t(x);
                    if (i < count) px.push_back(std::uint32_t(i));
                }
    return px;
}

/// One pass of jittered primary rays through the pixels `px` (pass p re-jitters).
std::vector<Ray> primary_pass(const Camera& cam, int width, const std::vector<std::uint32_t>& px,
                              std::uint64_t seed, std::uint64_t pass) {
    std::vector<Ray> rays(px.size());
    for (std::size_t k = 0; k < px.size(); ++k) {
        const std::uint32_t i = px[k];
        const float jx = u01(seed, stream_jitter + 4 * pass, i), jy = u01(seed, stream_jitter + 4 * pass + 1, i);
        rays[k] = cam.ray(float(i % std::uint32_t(width)) + jx, float(i / std::uint32_t(width)) + jy);
    }
    return rays;
}

/// Cosine-weighted direction around unit n. Orthonormal basis from "Building an Orthonormal
/// Basis, Revisited", Duff et al., JCGT 2017.
Vec3f cosine_direction(const Vec3f& n, float u1, float u2) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    const Vec3f t{1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
    const Vec3f s{b, sign + n.y * n.y * a, -n.y};
    const float r = std::sqrt(u1), phi = 2.0f * std::numbers::pi_v<float> * u2;
    const float z = std::sqrt(std::max(0.0f, 1.0f - u1));
    return simd::normalize(t * (r * std::cos(phi)) + s * (r * std::sin(phi)) + n * z);
}

Vec3f uniform_direction(float u1, float u2) {
    const float z = 1.0f - 2.0f * u1;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 2.0f * std::numbers::pi_v<float> * u2;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

std::vector<Ray> random_rays(const accel::Bounds& b, std::size_t count, std::uint64_t seed) {
    std::vector<Ray> rays(count);
    const Vec3f ext = b.extent();
    for (std::size_t i = 0; i < count; ++i) {
        Ray& r = rays[i];
        r.org = {b.lo.x + u01(seed, stream_random + 0, i) * ext.x, b.lo.y + u01(seed, stream_random + 1, i) * ext.y,
                 b.lo.z + u01(seed, stream_random + 2, i) * ext.z};
        // The box is closed: a coordinate rounded past hi is clamped back in.
        r.org = simd::vmin(r.org, b.hi);
        r.dir = uniform_direction(u01(seed, stream_random + 3, i), u01(seed, stream_random + 4, i));
    }
    return rays;
}

}  // namespace

std::string_view to_string(RayKind k) {
    for (const auto& [kind, name] : kind_names)
        if (kind == k) return name;
    return "?";
}

std::optional<RayKind> parse_ray_kind(std::string_view s) {
    for (const auto& [kind, name] : kind_names)
        if (name == s) return kind;
    return std::nullopt;
}

std::optional<PixelOrder> parse_pixel_order(std::string_view s) {
    if (s == "tiles") return PixelOrder::tiles;
    if (s == "rows") return PixelOrder::rows;
    return std::nullopt;
}

Sphere bounding_sphere(const accel::Bounds& b) {
    if (b.empty()) return {Vec3f{0.0f}, 1.0f};
    return {b.center(), std::max(0.5f * simd::length(b.extent()), 1e-6f)};
}

Camera framed_camera(const accel::Bounds& b, int width, int height) {
    const Sphere s = bounding_sphere(b);
    constexpr float distance = 2.5f;  // in radii
    Camera c;
    c.look_at = s.center;
    c.eye = s.center + simd::normalize(Vec3f{0.55f, 0.35f, 1.0f}) * (distance * s.radius);
    c.up = {0.0f, 1.0f, 0.0f};
    // Half-diagonal of the image at 97% of the sphere's angular radius, so that corner rays
    // still hit the sphere after rounding.
    const float half_diag = std::tan(0.97f * std::asin(1.0f / distance));
    const float aspect = float(width) / float(height);
    const float half_h = half_diag / std::sqrt(1.0f + aspect * aspect);
    c.vfov_degrees = 2.0f * std::atan(half_h) * 180.0f / std::numbers::pi_v<float>;
    return c;
}

void primary_image_size(std::size_t count, float aspect, int& width, int& height) {
    count = std::max<std::size_t>(count, 1);
    width = std::max(1, int(std::lround(std::sqrt(double(count) * aspect))));
    height = int((count + std::size_t(width) - 1) / std::size_t(width));
}

RayGenScene ray_gen_scene(const Scene& scene, bool use_scene_camera) {
    RayGenScene r;
    r.tris = scene.mesh.view();
    r.bounds = scene.mesh.bounds;
    if (!scene.lights.empty()) {
        r.light = scene.lights.front().position;
    } else {  // where scene_from_mesh puts its light
        const Vec3f ext = r.bounds.extent();
        const float size = std::max(ext.x, std::max(ext.y, ext.z));
        r.light = r.bounds.center() + Vec3f{0.5f * size, 1.5f * size, 1.5f * size};
    }
    if (use_scene_camera) r.camera = scene.camera;
    return r;
}

std::vector<Ray> generate_rays(const RayGenScene& scene, const RayGenConfig& cfg, const accel::Accel* tracer) {
    if (!tracer) return generate_rays(scene, cfg, PrimaryTracer{});
    return generate_rays(scene, cfg, [tracer](std::span<const Ray> rays, std::span<Hit> hits) {
        accel::trace_parallel(*tracer, rays, hits, accel::Query::closest);
    });
}

std::vector<Ray> generate_rays(const RayGenScene& scene, const RayGenConfig& cfg, const PrimaryTracer& tracer) {
    if (cfg.kind == RayKind::random) return random_rays(scene.bounds, cfg.count, cfg.seed);

    int width = 0, height = 0;
    primary_image_size(cfg.count, cfg.aspect, width, height);
    Camera cam = scene.camera ? *scene.camera : framed_camera(scene.bounds, width, height);
    cam.prepare(width, height);
    const std::vector<std::uint32_t> px = pixel_order(width, height, cfg.count, cfg.order, cfg.tile_size);
    if (cfg.kind == RayKind::primary) return primary_pass(cam, width, px, cfg.seed, 0);

    if (!tracer) throw std::invalid_argument("generate_rays: shadow and diffuse rays need a tracer");
    const ShadowLight light(scene, cfg.shadow, cfg.seed);
    constexpr std::uint64_t max_passes = 256;
    std::vector<Ray> out;
    out.reserve(cfg.count);
    std::vector<Hit> hits(px.size());
    for (std::uint64_t pass = 0; pass < max_passes && out.size() < cfg.count; ++pass) {
        const std::vector<Ray> prim = primary_pass(cam, width, px, cfg.seed, pass);
        tracer(prim, hits);
        const std::size_t before = out.size();
        for (std::size_t i = 0; i < prim.size() && out.size() < cfg.count; ++i) {
            if (!hits[i].is_hit()) continue;
            const HitGeometry g = hit_geometry(scene.tris, prim[i], hits[i]);
            if (!g.valid) continue;
            Vec3f n = g.normal;
            Ray r;
            if (cfg.kind == RayKind::shadow) {
                const Vec3f target = light.point(pass * cfg.count + i);
                r.org = accel::offset_ray_origin(g.position, n, g.scale);
                r.dir = target - r.org;
                if (!(simd::dot(r.dir, n) > 0.0f)) {
                    if (!cfg.shadow.from_all) continue;  // the light is behind the surface
                    n = n * -1.0f;                        // start on the far side: the ray crosses the model
                    r.org = accel::offset_ray_origin(g.position, n, g.scale);
                    r.dir = target - r.org;
                }
                r.tfar = 0.9999f;  // t = 1 is the light itself
            } else {
                r.org = accel::offset_ray_origin(g.position, n, g.scale);
                const std::uint64_t id = pass * cfg.count + i;
                r.dir = cosine_direction(n, u01(cfg.seed, stream_diffuse, id), u01(cfg.seed, stream_diffuse + 1, id));
            }
            out.push_back(r);
        }
        const std::size_t made = out.size() - before;
        if (pass == 0 && made * max_passes < cfg.count)
            throw InputError("scene: only " + std::to_string(made) + " of " + std::to_string(px.size()) +
                             " primary rays found a usable hit point; cannot make " + std::to_string(cfg.count) + " " +
                             std::string(to_string(cfg.kind)) + " rays");
    }
    if (out.size() < cfg.count)
        throw InputError("scene: too few usable primary hit points for " + std::to_string(cfg.count) + " " +
                         std::string(to_string(cfg.kind)) + " rays");
    return out;
}

std::unique_ptr<accel::Accel> make_ray_gen_tracer(const accel::TriangleView& tris) {
    using accel::AccelKind;
    for (const AccelKind k : {AccelKind::bvh_sah, AccelKind::lbvh, AccelKind::bvh_median, AccelKind::kdtree}) {
        try {
            return accel::make_accel(k, tris);
        } catch (const std::invalid_argument&) {
            // not in this build yet
        }
    }
    return accel::make_accel(AccelKind::brute, tris);
}

}  // namespace arbor::engine
