#pragma once
/// What every integrator shares: the read-only render context, the per-tile film, the camera
/// batch of a tile, and the surface record of a hit. Integrators work a tile at a time in
/// waves: all camera rays of a pass go to the structure as one batch, then all shadow rays of
/// that wave, then all bounce rays, and so on.
#include "engine/camera.h"
#include "engine/lights.h"
#include "engine/plan.h"
#include "engine/sampling.h"
#include "engine/tracer.h"

#include <memory>
#include <vector>

namespace arbor::engine {

struct Tile {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< pixels [x0, x1) x [y0, y1)
    int width() const { return x1 - x0; }
    int pixels() const { return (x1 - x0) * (y1 - y0); }
};

/// Sums of a tile's samples, per pixel (index (y - y0) * width + (x - x0)).
struct TileFilm {
    Tile tile;
    std::vector<Vec3f> color;  ///< radiance sums
    std::vector<float> depth;  ///< smallest camera-space depth (+inf: no hit); only with the Z layer
    std::vector<Vec3f> normal, albedo;  ///< sums; only with the N / A layers

    TileFilm(const Tile& t, const Layers& layers);
};

/// Everything an integrator reads; shared by all threads.
struct RenderContext {
    const Scene& scene;
    const Camera& camera;  ///< prepared for the image size
    const LightSet& lights;
    const RenderPlan& plan;
    const RenderSettings& settings;

    RenderContext(const Scene& s, const Camera& c, const LightSet& l, const RenderPlan& p, const RenderSettings& set);
    RenderContext(const RenderContext&) = delete;  // single_ may point at fallback_
    RenderContext& operator=(const RenderContext&) = delete;

    /// The material of triangle `prim`; one fixed material when the plan skips per-hit lookups.
    const Material& material(std::uint32_t prim) const {
        return single_ ? *single_ : scene.mesh.materials[scene.mesh.material[prim]];
    }

private:
    Material fallback_{};
    const Material* single_ = nullptr;
};

/// A path (or camera sample) in flight: which pixel of the tile, its random stream, its weight.
struct PathState {
    std::uint32_t pixel = 0;  ///< index in the tile film
    SampleStream rng;
    Vec3f throughput{1.0f};
    bool specular = true;  ///< the last scattering was a camera or mirror event (emission counts)
};

/// Fills `rays` and `paths` with the camera rays of samples [s0, s1) of every pixel of `tile`
/// (pixel-major: all samples of a pixel are neighbours in the batch).
void camera_batch(const RenderContext& ctx, const Tile& tile, int s0, int s1, std::vector<accel::Ray>& rays,
                  std::vector<PathState>& paths);

/// Number of samples per pass so that a tile's camera batch holds about 4096 rays.
int samples_per_pass(const Tile& tile, int spp);

/// The surface seen by a hit: position (when the plan needs it), unit geometric normal turned
/// against the ray, shading normal, albedo and material (engine/shading.h).
struct Surface {
    Vec3f position{0.0f};
    Vec3f normal{0.0f, 0.0f, 1.0f};   ///< geometric, facing the ray: offsets and the side rays leave on
    Vec3f shading{0.0f, 0.0f, 1.0f};  ///< for cosines and scattering (= normal without vertex normals)
    Vec3f albedo{0.0f};               ///< diffuse reflectance here (material x texture x vertex colour)
    Vec3f origin{0.0f};               ///< where secondary rays start (offset; Hanika's point with vertex normals)
    float scale = 0.0f;  ///< accel::triangle_scale of the hit triangle (for offset_ray_origin)
    const Material* material = nullptr;
    bool valid = false;  ///< false for zero-area triangles (the hit is then ignored)
};

Surface surface_at(const RenderContext& ctx, const accel::Ray& ray, const accel::Hit& hit);

/// Records the first-hit layers (depth, normal, albedo) that the plan asks for.
void record_layers(const RenderContext& ctx, TileFilm& film, std::uint32_t pixel, const accel::Hit& hit,
                   const Surface& s);

/// A shadow ray waiting for its answer: whom it lights and by how much when unoccluded.
struct ShadowBatch {
    std::vector<accel::Ray> rays;
    std::vector<accel::Hit> hits;
    std::vector<std::uint32_t> pixel;
    std::vector<Vec3f> contribution;

    void clear() { rays.clear(), pixel.clear(), contribution.clear(); }
    void add(const accel::Ray& r, std::uint32_t px, const Vec3f& c) {
        rays.push_back(r), pixel.push_back(px), contribution.push_back(c);
    }
    /// Traces the batch (any-hit) and adds the contributions of unoccluded rays to the film.
    void resolve(Tracer& tracer, TileFilm& film);
};

/// Direct light at a diffuse surface point (albedo > 0): one shadow ray per point light, one to a
/// point on an area light drawn by power (next-event estimation) and one cosine-weighted ray to
/// the sky, as the plan allows. `weight` multiplies every contribution (the path throughput).
void sample_direct_light(const RenderContext& ctx, const Surface& s, const Vec3f& weight, PathState& path,
                         ShadowBatch& shadows);

/// The perfect mirror direction of `dir` about the shading normal, or about the geometric normal
/// when the first would go below the surface.
Vec3f mirror_direction(const Surface& s, const Vec3f& dir);

class Integrator {
public:
    virtual ~Integrator() = default;
    /// Adds all spp samples of every pixel of film.tile into film. Thread-safe (const; state in
    /// the arguments); the result depends only on the tile and the context.
    virtual void render_tile(const RenderContext& ctx, Tracer& tracer, TileFilm& film) const = 0;
};

std::unique_ptr<Integrator> make_primary_integrator();
std::unique_ptr<Integrator> make_ao_integrator();
std::unique_ptr<Integrator> make_direct_integrator();
std::unique_ptr<Integrator> make_path_integrator();
/// Nodes visited and triangles tested per camera ray, in the film's first two colour sums.
std::unique_ptr<Integrator> make_cost_integrator();
std::unique_ptr<Integrator> make_integrator(IntegratorKind kind);

}  // namespace arbor::engine
