/// The field scene: N x N instances (default 100 x 100: 10,000) of four procedural models of
/// 82k to 328k triangles (two jittered icospheres, a flat torus and a standing ring), each turned,
/// scaled and some mirrored, on a ground plane under a point light. The models are held
/// once (0.7 million unique triangles); the default field places 1.75 billion.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "engine/builtin_scenes.h"
#include "engine/procedural.h"

namespace arbor::engine {

namespace {

/// A uniform number in [0, 1) from (i, j, k): the same field on every machine.
float field_random(int i, int j, int k) {
    std::uint64_t h =
        (std::uint64_t(std::uint32_t(i)) << 32) ^ (std::uint64_t(std::uint32_t(j)) << 8) ^ std::uint64_t(k);
    h += 0x9E3779B97F4A7C15ull;
    h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
    h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
    h ^= h >> 31;
    return float(h >> 40) * (1.0f / 16777216.0f);
}

/// The field's models, each standing on y = 0, centred on the y axis, 1 high.
std::vector<Mesh> field_models() {
    std::vector<Mesh> out;
    out.push_back(make_icosphere({0, 0, 0}, 1.0f, 6, 0.12f, 7));   // 81,920 triangles
    out.push_back(make_icosphere({0, 0, 0}, 1.0f, 7, 0.04f, 11));  // 327,680
    out.push_back(make_torus({0, 0, 0}, 1.0f, 0.4f, 400, 200));    // 160,000
    Mesh ring = make_torus({0, 0, 0}, 1.0f, 0.15f, 256, 256);      // 131,072, stood up (y <-> z)
    std::swap(ring.y, ring.z);
    for (std::size_t t = 0; t < ring.triangle_count(); ++t) std::swap(ring.indices[3 * t + 1], ring.indices[3 * t + 2]);
    out.push_back(std::move(ring));
    for (Mesh& m : out) {
        place_on_floor(m, 1.0f, 0.0f, 0.0f, 0.0f);
        // At most 1.2 wide, so that neighbours 1.6 apart seldom touch.
        const float wide = std::max(m.bounds.extent().x, m.bounds.extent().z);
        if (wide > 1.2f) {
            const float k = 1.2f / wide;
            for (std::size_t v = 0; v < m.vertex_count(); ++v) m.x[v] *= k, m.y[v] *= k, m.z[v] *= k;
            m.compute_bounds();
        }
    }
    return out;
}

}  // namespace

Scene make_field_scene(int n) {
    Scene s;
    s.name = "field-" + std::to_string(n) + "x" + std::to_string(n);
    const float spacing = 1.6f, half = 0.5f * spacing * float(n);
    s.mesh = with_material(make_ground(0.0f, 0.0f, 0.0f, half + 1.0f), {"ground", {0.6f, 0.6f, 0.58f}, {}, {}});
    s.placed.drawn = std::uint32_t(s.mesh.triangle_count());
    const Material looks[4] = {{"clay", {0.7f, 0.55f, 0.4f}, {}, {}},
                               {"sage", {0.45f, 0.6f, 0.45f}, {}, {}},
                               {"slate", {0.4f, 0.45f, 0.6f}, {}, {}},
                               {"brass", {0.75f, 0.65f, 0.3f}, {}, {}}};
    std::vector<Mesh> models = field_models();
    for (std::size_t p = 0; p < models.size(); ++p) {
        const auto first = std::uint32_t(s.mesh.triangle_count()), v = std::uint32_t(s.mesh.vertex_count());
        s.mesh.append(with_material(std::move(models[p]), looks[p]));
        s.placed.parts.push_back(
            {first, std::uint32_t(s.mesh.triangle_count()) - first, std::uint32_t(s.mesh.vertex_count()) - v});
    }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const auto part = std::uint32_t(field_random(i, j, 0) * 4.0f) % 4;
            const double angle = 2.0 * std::numbers::pi * double(field_random(i, j, 1));
            const double scale = 0.55 + 0.35 * double(field_random(i, j, 2));
            const double mirror = field_random(i, j, 3) < 0.25f ? -1.0 : 1.0;  // a quarter are mirrored
            const double x = (double(i) + 0.5) * spacing - half + 0.2 * (double(field_random(i, j, 4)) - 0.5);
            const double z = (double(j) + 0.5) * spacing - half + 0.2 * (double(field_random(i, j, 5)) - 0.5);
            const double c = std::cos(angle), sn = std::sin(angle);
            PartInstance inst;
            inst.part = part;
            // R_y(angle) * diag(mirror * scale, scale, scale), then the move to (x, 0, z).
            inst.transform.m = {c * mirror * scale,   0.0, sn * scale, x, 0.0, scale, 0.0, 0.0,
                                -sn * mirror * scale, 0.0, c * scale,  z};
            s.placed.instances.push_back(inst);
        }
    s.mesh.compute_bounds();
    s.placed.index(s.mesh, "builtin:field");
    s.camera.eye = {0.35f * half, 0.35f * half + 1.5f, 1.25f * half + 1.0f};
    s.camera.look_at = {0.0f, 0.2f, 0.1f * half};
    s.camera.vfov_degrees = 45.0f;
    s.lights.push_back({{half, 3.0f * half + 2.0f, 1.5f * half}, Vec3f{1.0f} * (9.0f * (half * half + 4.0f))});
    s.background = {0.5f, 0.6f, 0.75f};
    return s;
}

}  // namespace arbor::engine
