/// The scaling scene: N x N copies of one model (the bunny when the shared models are there,
/// a 81,920-triangle jittered icosphere otherwise) on a ground plane under a point light and a
/// sky. 6 x 6 bunnies are 2.5 million triangles.
#include "engine/builtin_scenes.h"
#include "engine/log.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"

#include <filesystem>

namespace arbor::engine {

Scene make_scaling_scene(int n) {
    Scene s;
    s.name = "scaling-" + std::to_string(n) + "x" + std::to_string(n);
    Mesh base;
    const std::string bunny = shared_models_dir() + "/stanford-bunny.obj";
    if (std::filesystem::exists(bunny)) {
        Warnings ignored;
        base = load_obj(bunny, ignored);
    } else {
        base = make_icosphere({0, 0, 0}, 1.0f, 6, 0.1f, 3);
    }
    place_on_floor(base, 1.0f, 0.0f, 0.0f, 0.0f);
    const float spacing = 1.6f, half = 0.5f * spacing * float(n);
    const Material ground{"ground", {0.6f, 0.6f, 0.58f}, {}, {}};
    const Material model{"model", {0.7f, 0.55f, 0.4f}, {}, {}};
    s.mesh = with_material(make_ground(0.0f, 0.0f, 0.0f, half + 1.0f), ground);
    Mesh copy = with_material(base, model);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const float dx = (float(i) + 0.5f) * spacing - half, dz = (float(j) + 0.5f) * spacing - half;
            for (std::size_t v = 0; v < copy.vertex_count(); ++v) {
                copy.x[v] = base.x[v] + dx;
                copy.z[v] = base.z[v] + dz;
            }
            copy.bounds = {{base.bounds.lo.x + dx, base.bounds.lo.y, base.bounds.lo.z + dz},
                           {base.bounds.hi.x + dx, base.bounds.hi.y, base.bounds.hi.z + dz}};
            s.mesh.append(copy);
        }
    s.mesh.compute_bounds();
    s.camera.eye = {0.35f * half, 0.9f * half + 1.0f, 1.6f * half + 1.0f};
    s.camera.look_at = {0.0f, 0.3f, -0.1f * half};
    s.camera.vfov_degrees = 45.0f;
    s.lights.push_back({{half, 3.0f * half + 2.0f, 1.5f * half}, Vec3f{1.0f} * (9.0f * (half * half + 4.0f))});
    s.background = {0.5f, 0.6f, 0.75f};
    return s;
}

}  // namespace arbor::engine
