#pragma once
/// The render plan: before any ray is traced, arbor works out what the scene and the integrator
/// need, and the integrators do only that work. No lights: no shadow rays. No mirror material:
/// no reflection rays. No emitter: no emission lookups. One material: no per-hit material lookup.
/// Layers nobody asked for are not computed. Everything left out is listed with its reason.
#include "engine/lights.h"
#include "engine/render_settings.h"

#include <string>
#include <vector>

namespace arbor::engine {

/// What the scene holds, as far as the plan cares (only materials used by some triangle count).
struct SceneTraits {
    bool diffuse = false;   ///< some triangle has Kd > 0
    bool mirror = false;    ///< some triangle has a mirror lobe (Ks with illum 3..7)
    bool emissive = false;  ///< some triangle has Ke > 0
    bool single_material = true;  ///< every triangle uses the same material
    bool textured = false;        ///< some used material has a texture and the mesh has texture coordinates
    bool texture_without_uv = false;  ///< a used material has a texture but no corner has coordinates
    bool background = false;      ///< misses see a non-black background
    std::size_t point_lights = 0, emitters = 0;
};

SceneTraits scene_traits(const Scene& scene, const LightSet& lights);

struct RenderPlan {
    IntegratorKind integrator = IntegratorKind::direct;
    int spp = 1, depth = 0;
    Layers layers;
    bool point_shadows = false;  ///< shadow rays to point lights
    bool area_shadows = false;   ///< next-event estimation: shadow rays to points on emissive triangles
    bool mirror = false;         ///< reflection rays from mirror materials
    bool diffuse = false;        ///< diffuse bounce rays (path)
    bool ao = false;             ///< ambient-occlusion rays
    bool emission = false;       ///< emission looked up where rays hit
    bool background = false;     ///< misses add the background radiance
    bool position = false;       ///< hit positions (needed by any secondary ray)
    bool material = false;       ///< per-hit material lookup (false: one material for all)
    bool vertex_normals = false; ///< shading normals interpolated from the corners (and Hanika's ray origins)
    bool textures = false;       ///< texture lookups at interpolated texture coordinates
    bool vertex_colors = false;  ///< interpolated vertex colours multiply the albedo
    bool sky_shadows = false;    ///< one shadow ray per diffuse hit toward the sky (Scene::sky_light)
    std::string lights;          ///< the lights arbor made for the scene (Scene::lights_note), if any
    float ao_radius = 0.0f;
    int ao_samples = 0;
    std::vector<std::string> skipped;  ///< "mirror rays: no mirror material", ...

    bool shadows() const { return point_shadows || area_shadows || sky_shadows; }
    /// The plan in one line (what will be traced and computed), naming the structure `accel`.
    std::string line(const std::string& accel) const;
    /// One line per skipped item, each "skipped: WHAT (WHY)".
    std::string skipped_lines() const;
};

/// Works out the plan for rendering `scene` with `settings`.
RenderPlan make_plan(const Scene& scene, const LightSet& lights, const RenderSettings& settings);

}  // namespace arbor::engine
