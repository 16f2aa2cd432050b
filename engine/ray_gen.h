#pragma once
/// Ray generation shared by tests, benchmarks and users (`arbor rays`): the four ray kinds a
/// renderer sends, for any scene, deterministic from a seed.
///   primary  pinhole camera over the framed scene (tile order, as a renderer sends them, or rows)
///   shadow   from primary hit points towards the light, tfar just short of the light
///   diffuse  cosine-weighted bounce rays from primary hit points
///   random   uniform origins inside the scene bounds, uniform directions
#include "accel/interface/accel.h"
#include "engine/camera.h"
#include "engine/scene.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

namespace arbor::engine {

enum class RayKind { primary, shadow, diffuse, random };
/// In which order the pixels of the primary image are visited (secondary rays follow it).
enum class PixelOrder { tiles, rows };

std::string_view to_string(RayKind k);
/// Parses "primary|shadow|diffuse|random"; nullopt for anything else.
std::optional<RayKind> parse_ray_kind(std::string_view s);
std::optional<PixelOrder> parse_pixel_order(std::string_view s);

/// How shadow rays are made, so that held-out sets are not one recipe (the defaults are the
/// benchmark's: a point light, only surface points facing it).
struct ShadowRecipe {
    /// 0: a point light. Above 0: a square area light of this side (times the scene's largest
    /// extent), centred on the light and facing the bounds' centre; each ray aims at its own point
    /// of it (drawn from the seed), as a renderer sampling an area light.
    float light_size = 0.0f;
    /// 0: the light where the scene or view puts it. Above 0: moved along the line from the bounds'
    /// centre through it to this many bounding radii (below 1: inside the bounding sphere, among
    /// the geometry: segments of all lengths).
    float light_distance = 0.0f;
    /// false: only points whose surface faces the light (a renderer's shadow rays; mostly
    /// unoccluded on a convex-ish model). true: every point, those facing away starting on the far
    /// side of their own surface, so that their rays cross the model (mostly occluded sets).
    bool from_all = false;
};

struct RayGenConfig {
    RayKind kind = RayKind::primary;
    std::size_t count = 1u << 20;          ///< exact number of rays returned
    std::uint64_t seed = 1;                ///< same seed, same rays (any thread count)
    PixelOrder order = PixelOrder::tiles;
    int tile_size = 8;                     ///< pixels per tile side in tile order
    float aspect = 4.0f / 3.0f;            ///< width / height of the primary image
    ShadowRecipe shadow;                   ///< shadow rays only
};

/// What the generator needs of a scene. The view must outlive the call.
struct RayGenScene {
    accel::TriangleView tris;
    accel::Bounds bounds;    ///< of the triangles (the random rays' box)
    Vec3f light;             ///< point light the shadow rays aim at
    /// The camera of primary rays; unset = framed_camera(bounds) (every ray hits the bounds' sphere).
    std::optional<Camera> camera;
};

/// A scene for ray generation from `scene`: its mesh, its first light (or one above the bounds
/// when it has none) and the framed camera (use_scene_camera = false) or the scene's own.
RayGenScene ray_gen_scene(const Scene& scene, bool use_scene_camera = false);

/// The bounding sphere of `b`: centre and radius (half the diagonal, at least 1e-6).
struct Sphere {
    Vec3f center;
    float radius;
};
Sphere bounding_sphere(const accel::Bounds& b);

/// A pinhole camera looking at the bounding sphere of `b` from the front-right-above (the
/// direction Camera::framing uses), at 2.5 radii, with the field of view chosen so that the whole
/// width x height image lies inside the sphere's disk: every primary ray hits the sphere.
Camera framed_camera(const accel::Bounds& b, int width, int height);

/// Image size for `count` primary rays at `aspect`: width * height >= count, the last row partial.
void primary_image_size(std::size_t count, float aspect, int& width, int& height);

/// Closest hits of a batch of primary rays over the scene's triangles (hits.size() == rays.size()).
using PrimaryTracer = std::function<void(std::span<const accel::Ray> rays, std::span<accel::Hit> hits)>;

/// Generates cfg.count rays of cfg.kind. Shadow and diffuse rays start at hit points of primary
/// rays traced with `tracer` (required for them; any correct tracer gives the same rays up to
/// ties): only hits facing the light make shadow rays, and passes of re-jittered primary rays are
/// traced until there are enough hits. Throws std::invalid_argument when a tracer is missing for
/// shadow/diffuse, and engine::InputError when the primary rays find (almost) no usable hit point.
std::vector<accel::Ray> generate_rays(const RayGenScene& scene, const RayGenConfig& cfg, const PrimaryTracer& tracer);
/// The same with an Accel built over scene.tris, traced with accel::trace_parallel (may be null
/// for primary and random rays).
std::vector<accel::Ray> generate_rays(const RayGenScene& scene, const RayGenConfig& cfg,
                                      const accel::Accel* tracer = nullptr);

/// The structure used to trace primary rays for shadow/diffuse generation: the first of bvh-sah,
/// lbvh, bvh-median, kdtree that this build provides, else brute.
std::unique_ptr<accel::Accel> make_ray_gen_tracer(const accel::TriangleView& tris);

}  // namespace arbor::engine
