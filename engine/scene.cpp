#include "engine/scene.h"

#include "engine/error.h"
#include "engine/memory_budget.h"
#include "engine/procedural.h"
#include "engine/smooth_normals.h"

#include <glm/glm.hpp>

#include <cstdio>

namespace arbor::engine {

Scene make_default_scene() {
    Scene s;
    s.name = "default";
    Material ground{"ground", {0.75f, 0.75f, 0.72f}, {}, {}};
    Material red{"red", {0.8f, 0.15f, 0.1f}, {}, {}};
    Material mirror{"mirror", {0.05f, 0.05f, 0.05f}, {0.9f, 0.9f, 0.9f}, {}};
    Material blue{"blue", {0.15f, 0.3f, 0.8f}, {}, {}};
    s.mesh = with_material(make_ground(0.0f, 0.0f, 0.0f, 6.0f), ground);
    // The sphere and the torus are smooth surfaces: vertex normals, so that the torus reflects
    // the scene without facets.
    Mesh sphere = make_icosphere({-1.2f, 1.0f, 0.0f}, 1.0f, 5, 0.0f), torus = make_torus({1.3f, 0.45f, 0.6f}, 0.8f, 0.35f, 96, 32);
    compute_smooth_normals(sphere);
    compute_smooth_normals(torus);
    s.mesh.append(with_material(std::move(sphere), red));
    s.mesh.append(with_material(std::move(torus), mirror));
    s.mesh.append(with_material(make_box({0.4f, 0.0f, -1.8f}, {1.6f, 1.4f, -0.9f}), blue));
    s.mesh.compute_bounds();
    s.camera.eye = {0.0f, 2.6f, 6.5f};
    s.camera.look_at = {0.0f, 0.7f, 0.0f};
    s.camera.vfov_degrees = 40.0f;
    s.lights.push_back({{3.0f, 6.0f, 4.0f}, {60.0f, 58.0f, 54.0f}});
    return s;
}

void flatten_instances(Scene& s, const std::string& what) {
    if (s.placed.empty()) return;
    const std::uint64_t need = flatten_bytes(s.mesh, s.placed), budget = memory_budget(0);
    if (need > budget / 2)
        throw InputError(what + ": " + std::to_string(s.placed.instances.size()) + " instances place " +
                         std::to_string(s.placed.effective_triangles()) +
                         " triangles; this command traces a flattened copy, which needs about " + format_bytes(need) +
                         ", more than half the " + format_bytes(budget) +
                         " of memory (arbor render, arbor view and arbor info trace the instances)");
    s.mesh = flatten(s.mesh, s.placed);
    s.placed = {};
}

Bounds scene_bounds(const Scene& scene) { return world_bounds(scene.mesh, scene.placed); }

Scene scene_from_mesh(Mesh mesh, std::string name, MeshInstances placed) {
    Scene s;
    s.name = std::move(name);
    const Bounds box = world_bounds(mesh, placed, true);
    s.camera = Camera::framing(box);
    const Vec3f ext = box.extent();
    const float size = std::max(ext.x, std::max(ext.y, ext.z));
    const Vec3f c = box.center();
    // Models with emissive materials are lit by them. Others get a light above and in front, at
    // about two model sizes, with an intensity that makes the irradiance at the model about 3.
    bool emissive = false;
    for (const Material& m : mesh.materials) emissive |= m.emission.x > 0.0f || m.emission.y > 0.0f || m.emission.z > 0.0f;
    if (!emissive) {
        const Vec3f light = c + Vec3f{0.5f * size, 1.5f * size, 1.5f * size};
        const Vec3f d = light - c;
        const float d2 = simd::dot(d, d);
        s.lights.push_back({light, Vec3f{1.0f} * (3.0f * d2)});
        s.made_light = true;
    }
    s.background = {0.2f, 0.2f, 0.22f};
    s.mesh = std::move(mesh);
    s.placed = std::move(placed);
    return s;
}

void light_from_camera(Scene& s) {
    if (!s.made_light || s.lights.empty()) return;
    const Camera& c = s.camera;
    const glm::vec3 eye(c.eye.x, c.eye.y, c.eye.z), at(c.look_at.x, c.look_at.y, c.look_at.z);
    const glm::vec3 forward = glm::normalize(at - eye);
    const glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(c.up.x, c.up.y, c.up.z)));
    const glm::vec3 up = glm::cross(right, forward);
    const float dist = glm::length(at - eye);
    // A photographer's key light: above and to the left of the camera, a little behind it, so
    // the side of the model facing the camera is lit from wherever the camera is.
    const glm::vec3 pos = eye + (up * 0.6f - right * 0.4f - forward * 0.2f) * dist;
    const float d2 = glm::dot(pos - at, pos - at);
    PointLight key{{pos.x, pos.y, pos.z}, Vec3f{2.0f * d2}};
    s.lights.front() = key;
    s.sky_light = !(s.background.x <= 0.0f && s.background.y <= 0.0f && s.background.z <= 0.0f);
    char buf[200];
    std::snprintf(buf, sizeof buf, "key light at (%.3g, %.3g, %.3g) beside the camera%s (made: the scene has none)",
                  double(pos.x), double(pos.y), double(pos.z), s.sky_light ? ", the background as a sky" : "");
    s.lights_note = buf;
}

void remove_made_lights(Scene& s) {
    if (s.made_light && !s.lights.empty()) s.lights.erase(s.lights.begin());
    s.made_light = false;
    s.sky_light = false;
    s.lights_note.clear();
}

}  // namespace arbor::engine
