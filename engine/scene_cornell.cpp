/// The Cornell box (Goral et al. 1984): white floor, ceiling and back wall, red left and green
/// right wall, a square area light under the ceiling, the Stanford bunny and a mirror sphere.
#include "engine/builtin_scenes.h"
#include "engine/log.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"

#include <filesystem>

namespace arbor::engine {

namespace {

/// The quad p, p + a, p + a + b, p + b as two triangles (normal along a x b).
Mesh make_quad(Vec3f p, Vec3f a, Vec3f b, const Material& m) {
    Mesh q;
    q.add_vertex(p);
    q.add_vertex(p + a);
    q.add_vertex(p + a + b);
    q.add_vertex(p + b);
    q.add_triangle(0, 1, 2);
    q.add_triangle(0, 2, 3);
    q.compute_bounds();
    return with_material(std::move(q), m);
}

/// The bunny when the shared models are there, a jittered icosphere otherwise.
Mesh cornell_model() {
    const std::string bunny = shared_models_dir() + "/stanford-bunny.obj";
    if (std::filesystem::exists(bunny)) {
        Warnings ignored;
        return load_obj(bunny, ignored);
    }
    return make_icosphere({0, 0, 0}, 1.0f, 4, 0.15f, 7);
}

}  // namespace

Scene make_cornell_scene() {
    Scene s;
    s.name = "cornell";
    const Material white{"white", {0.73f, 0.73f, 0.73f}, {}, {}};
    const Material red{"red", {0.65f, 0.05f, 0.05f}, {}, {}};
    const Material green{"green", {0.12f, 0.45f, 0.15f}, {}, {}};
    const Material light{"light", {0.78f, 0.78f, 0.78f}, {}, {17.0f, 12.0f, 4.0f}};
    const Material model{"model", {0.75f, 0.7f, 0.55f}, {}, {}};
    const Material mirror{"mirror", {0.0f, 0.0f, 0.0f}, {0.9f, 0.9f, 0.9f}, {}};
    // The box spans [-1, 1] x [0, 2] x [-1, 1]; the camera looks in through the open front (z = 1).
    s.mesh = make_quad({-1, 0, -1}, {0, 0, 2}, {2, 0, 0}, white);   // floor, normal +y
    s.mesh.append(make_quad({-1, 2, -1}, {2, 0, 0}, {0, 0, 2}, white));    // ceiling, normal -y
    s.mesh.append(make_quad({-1, 0, -1}, {2, 0, 0}, {0, 2, 0}, white));    // back wall, normal +z
    s.mesh.append(make_quad({-1, 0, -1}, {0, 2, 0}, {0, 0, 2}, red));      // left wall, normal +x
    s.mesh.append(make_quad({1, 0, -1}, {0, 0, 2}, {0, 2, 0}, green));     // right wall, normal -x
    s.mesh.append(make_quad({-0.25f, 1.995f, -0.25f}, {0.5f, 0, 0}, {0, 0, 0.5f}, light));  // area light
    Mesh m = cornell_model();
    place_on_floor(m, 0.9f, -0.3f, -0.2f, 0.0f);
    s.mesh.append(with_material(std::move(m), model));
    s.mesh.append(with_material(make_icosphere({0.5f, 0.35f, 0.35f}, 0.35f, 4), mirror));
    s.mesh.compute_bounds();
    s.camera.eye = {0.0f, 1.0f, 3.9f};
    s.camera.look_at = {0.0f, 1.0f, 0.0f};
    s.camera.vfov_degrees = 40.0f;
    s.background = {0.0f, 0.0f, 0.0f};
    return s;
}

}  // namespace arbor::engine
