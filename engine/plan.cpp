#include "engine/plan.h"

#include "engine/sampling.h"

#include <cmath>

namespace arbor::engine {

SceneTraits scene_traits(const Scene& scene, const LightSet& lights) {
    SceneTraits t;
    const Mesh& m = scene.mesh;
    std::vector<char> used(std::max<std::size_t>(1, m.materials.size()), 0);
    if (m.material.empty()) used[0] = 1;
    for (std::uint32_t id : m.material) used[id] = 1;
    const Material fallback{};
    int used_count = 0;
    for (std::size_t i = 0; i < used.size(); ++i) {
        if (!used[i]) continue;
        ++used_count;
        const Material& mat = m.materials.empty() ? fallback : m.materials[i];
        t.diffuse |= !is_black(mat.diffuse);
        t.mirror |= !is_black(mat.mirror);
        t.emissive |= !is_black(mat.emission);
        if (mat.diffuse_texture >= 0) (m.has_uvs() ? t.textured : t.texture_without_uv) = true;
    }
    t.single_material = used_count <= 1;
    t.background = !is_black(scene.background);
    t.point_lights = lights.points().size();
    t.emitters = lights.emitter_count();
    return t;
}

RenderPlan make_plan(const Scene& scene, const LightSet& lights, const RenderSettings& set) {
    const SceneTraits t = scene_traits(scene, lights);
    RenderPlan p;
    p.integrator = set.integrator;
    p.spp = set.spp;
    p.depth = set.depth();
    const bool cost = set.integrator == IntegratorKind::cost;
    p.layers = cost ? Layers{} : set.resolved_layers();
    auto skip = [&](const std::string& what, const std::string& why) { p.skipped.push_back(what + " (" + why + ")"); };
    const bool lit = set.integrator == IntegratorKind::direct || set.integrator == IntegratorKind::path;

    if (set.integrator == IntegratorKind::ao) {
        const Vec3f ext = scene_bounds(scene).extent();
        p.ao_radius = set.ao_radius >= 0.0f ? set.ao_radius : 0.25f * std::sqrt(simd::dot(ext, ext));
        p.ao_samples = set.ao_samples;
        p.ao = p.ao_radius > 0.0f && p.ao_samples > 0 && std::isfinite(p.ao_radius);
        if (!p.ao) skip("ambient-occlusion rays", "radius or sample count is zero: every pixel is unoccluded");
    }
    if (!lit) {
        skip("shadow, mirror and bounce rays", "the " + std::string(to_string(set.integrator)) +
                                                   " integrator traces camera rays" +
                                                   (set.integrator == IntegratorKind::ao ? " and AO rays only" : " only"));
    } else {
        if (t.point_lights == 0) skip("shadow rays to point lights", "the scene has no point light");
        else if (!t.diffuse) skip("shadow rays to point lights", "no diffuse surface to light");
        else p.point_shadows = true;
        if (t.emitters == 0) skip("shadow rays to area lights", "no emissive triangle");
        else if (!t.diffuse) skip("shadow rays to area lights", "no diffuse surface to light");
        else p.area_shadows = true;
        const bool dark = t.point_lights == 0 && t.emitters == 0 && !t.background;  // a sky needs a background too
        const std::string dark_reason = "nothing emits light: no light, no emitter, black background";
        if (!t.mirror) skip("mirror rays", "no mirror material (MTL illum 3..7 with Ks > 0)");
        else if (p.depth == 0) skip("mirror rays", "--depth 0");
        else if (dark) skip("mirror rays", dark_reason);
        else p.mirror = true;
        if (scene.sky_light && t.background && t.diffuse) p.sky_shadows = true;
        else if (t.background) skip("shadow rays to the sky", "the background only colours rays that escape");
        p.emission = t.emissive;
        if (!t.emissive) skip("emission lookups", "no emissive material");
        if (set.integrator == IntegratorKind::path) {
            if (!t.diffuse) skip("diffuse bounces", "no diffuse material");
            else if (p.depth == 0) skip("diffuse bounces", "--depth 0");
            else if (dark) skip("diffuse bounces", dark_reason);
            else p.diffuse = true;
        }
    }
    const bool shaded = set.integrator != IntegratorKind::ao && !cost;
    p.background = t.background && shaded;
    if (!t.background && shaded) skip("background radiance", "the background is black");
    if (cost) skip("shading, background and layers Z, N, A", "the cost integrator writes the layers nodes and tris only");
    p.position = p.shadows() || p.mirror || p.diffuse || p.ao;
    p.lights = scene.lights_note;
    if (!p.position) skip("hit positions", "no secondary ray starts at a hit");
    const bool wants_material = shaded || p.layers.albedo;
    p.material = wants_material && !t.single_material;
    if (wants_material && t.single_material) skip("per-hit material lookup", "every triangle uses one material");
    if (!p.layers.depth && !cost) skip("depth layer Z", "not requested");
    if (!p.layers.normal && !cost) skip("normal layer N", "not requested");
    if (!p.layers.albedo && !cost) skip("albedo layer A", "not requested");
    if (cost) return p;  // the cost integrator shades nothing: no attribute is read
    // Shading attributes: read only where the scene has them and the integrator looks.
    const Mesh& mesh = scene.mesh;
    p.vertex_normals = mesh.has_normals();
    if (!p.vertex_normals) skip("vertex normals", "the model has none, so flat shading; --smooth computes them");
    const bool albedo = shaded || p.layers.albedo;
    if (!albedo) {
        if (t.textured || !mesh.colors.empty())
            skip("textures and vertex colours", "the ao integrator without the albedo layer reads no colour");
    } else {
        p.textures = t.textured;
        p.vertex_colors = !mesh.colors.empty();
    }
    if (t.texture_without_uv) skip("textures", "the model has no texture coordinates");
    else if (!t.textured) skip("texture coordinates and textures", "no material has a texture");
    if (mesh.colors.empty()) skip("vertex colours", "the model has none");
    return p;
}

std::string RenderPlan::line(const std::string& accel) const {
    std::string s = "plan: " + std::string(to_string(integrator)) + ", " + std::to_string(spp) + " spp";
    if (mirror || diffuse) s += ", depth " + std::to_string(depth);
    s += ", structure " + accel + "; rays: camera";
    if (point_shadows) s += ", shadow(point)";
    if (area_shadows) s += ", shadow(area NEE)";
    if (sky_shadows) s += ", shadow(sky)";
    if (mirror) s += ", mirror";
    if (diffuse) s += ", diffuse(RR)";
    if (ao) s += ", ao(" + std::to_string(ao_samples) + ")";
    if (integrator == IntegratorKind::cost) {
        s += "; per ray: nodes visited, triangles tested (statistics mode); layers: nodes tris";
        return s + "; " + std::to_string(skipped.size()) + " items skipped";
    }
    s += "; per hit:";
    s += position ? " position" : "";
    s += vertex_normals ? " normal(interpolated)" : " normal";
    s += material ? " material" : "";
    s += emission ? " emission" : "";
    s += textures ? " texture" : "";
    s += vertex_colors ? " vertex-colour" : "";
    s += "; layers: RGB";
    if (layers.depth) s += " Z";
    if (layers.normal) s += " N";
    if (layers.albedo) s += " A";
    if (!lights.empty()) s += "; lights: " + lights;
    s += "; " + std::to_string(skipped.size()) + " items skipped";
    return s;
}

std::string RenderPlan::skipped_lines() const {
    std::string s;
    for (const auto& k : skipped) s += "skipped: " + k + "\n";
    return s;
}

}  // namespace arbor::engine
