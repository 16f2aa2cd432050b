#include "engine/renderer.h"

#include "accel/offset_ray.h"
#include "accel/timer.h"

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <mutex>
#include <numbers>
#include <unistd.h>

namespace arbor::engine {

namespace {

using accel::Hit;
using accel::Ray;
using simd::dot;

/// Deterministic per-(pixel, sample, dimension) random number in [0, 1).
float random01(std::uint32_t pixel, std::uint32_t sample, std::uint32_t dim) {
    std::uint64_t x = (std::uint64_t(pixel) << 32) ^ (std::uint64_t(sample) << 8) ^ dim;
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    x ^= x >> 31;
    return float(x >> 40) * (1.0f / 16777216.0f);
}

struct Path {
    std::uint32_t pixel;
    Vec3f throughput;
};

struct TileWork {
    std::vector<Ray> rays, shadow_rays;
    std::vector<Hit> hits, shadow_hits;
    std::vector<Path> paths, next_paths;
    std::vector<Ray> next_rays;
    std::vector<std::uint32_t> shadow_owner;
    std::vector<Vec3f> shadow_contrib;
};

class TileRenderer {
public:
    TileRenderer(const Scene& s, const accel::Accel& a, const RenderSettings& st) : scene_(s), accel_(a), set_(st) {}

    void render_tile(int x0, int x1, int y0, int y1, Image& img, RenderStats& local) const {
        TileWork w;
        const int tw = x1 - x0, th = y1 - y0;
        std::vector<Vec3f> sum(std::size_t(tw * th), Vec3f{0.0f});
        const int strata = std::max(1, int(std::sqrt(float(set_.spp))));
        for (int s = 0; s < set_.spp; ++s) {
            w.rays.clear();
            w.paths.clear();
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) {
                    const auto pixel = std::uint32_t(y * set_.width + x);
                    // Stratified jitter while s < strata^2, random beyond.
                    float jx = random01(pixel, std::uint32_t(s), 0), jy = random01(pixel, std::uint32_t(s), 1);
                    if (s < strata * strata) {
                        jx = (float(s % strata) + jx) / float(strata);
                        jy = (float(s / strata) + jy) / float(strata);
                    }
                    w.rays.push_back(scene_.camera.ray(float(x) + jx, float(y) + jy));
                    w.paths.push_back({std::uint32_t((y - y0) * tw + (x - x0)), Vec3f{1.0f}});
                }
            local.primary += w.rays.size();
            for (int depth = 0; !w.rays.empty(); ++depth) shade_bounce(w, sum, depth, local);
        }
        const float inv = 1.0f / float(set_.spp);
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                const Vec3f c = sum[std::size_t((y - y0) * tw + (x - x0))] * inv;
                img.at(0, x, y) = c.x;
                img.at(1, x, y) = c.y;
                img.at(2, x, y) = c.z;
            }
    }

private:
    void shade_bounce(TileWork& w, std::vector<Vec3f>& sum, int depth, RenderStats& local) const {
        w.hits.resize(w.rays.size());
        accel_.intersect(w.rays, w.hits, accel::TracePath::best);
        w.shadow_rays.clear();
        w.shadow_owner.clear();
        w.shadow_contrib.clear();
        w.next_rays.clear();
        w.next_paths.clear();
        const Mesh& m = scene_.mesh;
        for (std::size_t i = 0; i < w.rays.size(); ++i) {
            const Ray& r = w.rays[i];
            const Hit& h = w.hits[i];
            Path& path = w.paths[i];
            if (!h.is_hit()) {
                sum[path.pixel] += path.throughput * scene_.background;
                continue;
            }
            const Material& mat = m.materials.empty() ? default_material_
                                                      : m.materials[m.material.empty() ? 0 : m.material[h.prim]];
            const Vec3f v0 = m.view().corner(h.prim, 0), v1 = m.view().corner(h.prim, 1), v2 = m.view().corner(h.prim, 2);
            const Vec3f p = v0 * (1.0f - h.u - h.v) + v1 * h.u + v2 * h.v;
            Vec3f n = simd::cross(v1 - v0, v2 - v0);
            const float nlen = simd::length(n);
            if (!(nlen > 0.0f)) continue;
            n = n / nlen;
            if (dot(n, r.dir) > 0.0f) n = -n;  // face the viewer
            sum[path.pixel] += path.throughput * mat.emission;
            const Vec3f origin = accel::offset_ray_origin(p, n);
            const bool diffuse = mat.diffuse.x > 0.0f || mat.diffuse.y > 0.0f || mat.diffuse.z > 0.0f;
            for (const PointLight& light : diffuse ? scene_.lights : std::vector<PointLight>{}) {
                const Vec3f to = light.position - origin;
                const float cos_theta = dot(n, to);
                if (!(cos_theta > 0.0f)) continue;  // light behind the surface: no shadow ray needed
                const float d2 = dot(to, to);
                const float g = cos_theta / (d2 * std::sqrt(d2));
                const Vec3f f = mat.diffuse * (1.0f / std::numbers::pi_v<float>);
                w.shadow_rays.push_back({origin, 0.0f, to, 1.0f});
                w.shadow_owner.push_back(path.pixel);
                w.shadow_contrib.push_back(path.throughput * f * light.intensity * g);
            }
            const bool mirror = mat.mirror.x > 0.0f || mat.mirror.y > 0.0f || mat.mirror.z > 0.0f;
            if (mirror && depth < set_.max_depth) {
                const Vec3f d = r.dir - n * (2.0f * dot(r.dir, n) / dot(n, n));
                w.next_rays.push_back({origin, 0.0f, d, INFINITY});
                w.next_paths.push_back({path.pixel, path.throughput * mat.mirror});
            }
        }
        if (!w.shadow_rays.empty()) {
            w.shadow_hits.resize(w.shadow_rays.size());
            accel_.occluded(w.shadow_rays, w.shadow_hits, accel::TracePath::best);
            local.shadow += w.shadow_rays.size();
            for (std::size_t i = 0; i < w.shadow_rays.size(); ++i)
                if (!w.shadow_hits[i].is_hit()) sum[w.shadow_owner[i]] += w.shadow_contrib[i];
        }
        local.bounce += w.next_rays.size();
        std::swap(w.rays, w.next_rays);
        std::swap(w.paths, w.next_paths);
    }

    const Scene& scene_;
    const accel::Accel& accel_;
    const RenderSettings& set_;
    const Material default_material_{};
};

}  // namespace

Image render(const Scene& scene_in, const accel::Accel& accel, const RenderSettings& set, RenderStats* stats) {
    const accel::Timer timer;
    Scene scene = scene_in;  // the camera is prepared for this image size
    scene.camera.prepare(set.width, set.height);
    Image img(set.width, set.height, {"R", "G", "B"});
    const TileRenderer tiles(scene, accel, set);
    std::atomic<std::uint64_t> primary{0}, shadow{0}, bounce{0};
    const int tiles_x = (set.width + set.tile - 1) / set.tile, tiles_y = (set.height + set.tile - 1) / set.tile;
    const int total = tiles_x * tiles_y;
    std::atomic<int> done{0};
    std::mutex print_mutex;
    const bool progress = set.progress && ::isatty(2);
    tbb::parallel_for(tbb::blocked_range2d<int>(0, tiles_y, 1, 0, tiles_x, 1), [&](const tbb::blocked_range2d<int>& r) {
        RenderStats local;
        for (int ty = r.rows().begin(); ty < r.rows().end(); ++ty)
            for (int tx = r.cols().begin(); tx < r.cols().end(); ++tx) {
                const int x0 = tx * set.tile, y0 = ty * set.tile;
                tiles.render_tile(x0, std::min(x0 + set.tile, set.width), y0, std::min(y0 + set.tile, set.height), img, local);
                const int d = ++done;
                if (progress && print_mutex.try_lock()) {
                    const double el = timer.seconds();
                    std::fprintf(stderr, "\rrendering %3d%%  %.1fs elapsed, ~%.1fs left ", 100 * d / total, el,
                                 el * double(total - d) / double(d));
                    print_mutex.unlock();
                }
            }
        primary += local.primary;
        shadow += local.shadow;
        bounce += local.bounce;
    });
    if (progress) std::fprintf(stderr, "\r%60s\r", "");
    if (stats) {
        stats->seconds = timer.seconds();
        stats->primary = primary;
        stats->shadow = shadow;
        stats->bounce = bounce;
    }
    return img;
}

}  // namespace arbor::engine
