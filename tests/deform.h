#pragma once
/// A deforming mesh for the refit tests: a model's rest positions displaced by travelling sine
/// waves, one pose per step (each pose from the rest positions, so poses do not drift).
#include "engine/mesh.h"
#include "engine/obj_loader.h"
#include "testing.h"

#include <cmath>
#include <vector>

namespace arbor::testing {

/// Writes pose `step` of `rest` into out.x/y/z (resized to rest's vertex count; indices copied):
/// x moves by amplitude * diag * sin(6 pi y / diag + 0.9 step), z by amplitude * diag *
/// cos(4 pi x / diag + 0.6 step), diag the rest box's diagonal; step 0 is displaced too.
inline void deform(const engine::Mesh& rest, engine::Mesh& out, int step, float amplitude = 0.04f) {
    const accel::Vec3f e = rest.bounds.extent();
    const float diag = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
    const float a = amplitude * diag, pi = 3.14159265f;
    out.x.resize(rest.x.size()), out.y.resize(rest.y.size()), out.z.resize(rest.z.size());
    if (out.indices != rest.indices) out.indices = rest.indices;
    for (std::size_t i = 0; i < rest.x.size(); ++i) {
        out.x[i] = rest.x[i] + a * std::sin(6.0f * pi * rest.y[i] / diag + 0.9f * float(step));
        out.y[i] = rest.y[i];
        out.z[i] = rest.z[i] + a * std::cos(4.0f * pi * rest.x[i] / diag + 0.6f * float(step));
    }
    out.compute_bounds();
}

/// The model the deformation tests move: the Stanford bunny (69,451 triangles); in the sanitized
/// builds, which run ~10x slower, spot (5,856): the bunny's builds and refits made the two
/// deforming-model tests 216 s of the ASan phase's 470 s on two cores.
inline engine::Mesh deforming_model() {
    engine::Warnings w;
#if defined(ARBOR_SANITIZED_BUILD)
    return engine::load_obj(shared_scenes_dir() + "/models/spot.obj", w);
#else
    return engine::load_obj(shared_scenes_dir() + "/models/stanford-bunny.obj", w);
#endif
}

/// The packed x, y, z of `m`'s vertices (the form Scene::update_vertices and add_mesh take).
inline std::vector<float> packed(const engine::Mesh& m) {
    std::vector<float> p(3 * m.vertex_count());
    for (std::size_t i = 0; i < m.vertex_count(); ++i) p[3 * i] = m.x[i], p[3 * i + 1] = m.y[i], p[3 * i + 2] = m.z[i];
    return p;
}

}  // namespace arbor::testing
