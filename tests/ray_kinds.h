#pragma once
/// Rays of every kind engine/ray_gen.h makes over a mesh, for the tests that hold the SIMD paths to
/// the scalar path and brute: primary, shadow (a point light; an area light; from every point, most
/// crossing the model), diffuse and random; and an even sample of a batch for the brute oracle.
#include "accel/interface/accel.h"
#include "engine/mesh.h"
#include "engine/ray_gen.h"

#include <algorithm>
#include <vector>

namespace arbor::testing {

/// `n` rays of each kind over `mesh` (the shadow recipes n/2 each), concatenated, from `seed`;
/// `tracer` traces the primary rays the others start from.
inline std::vector<accel::Ray> ray_kinds(const engine::Mesh& mesh, std::size_t n, const accel::Accel& tracer,
                                         std::uint64_t seed) {
    engine::Scene scene;  // no lights: ray_gen_scene puts the light where `arbor rays` does
    scene.mesh = mesh;
    const engine::RayGenScene gs = engine::ray_gen_scene(scene);
    engine::ShadowRecipe area, all;
    area.light_size = 0.5f;
    all.from_all = true;
    struct Set {
        engine::RayKind kind;
        engine::ShadowRecipe shadow;
        std::size_t count;
    };
    const Set sets[] = {{engine::RayKind::primary, {}, n},        {engine::RayKind::shadow, {}, n},
                        {engine::RayKind::shadow, area, n / 2},   {engine::RayKind::shadow, all, n / 2},
                        {engine::RayKind::diffuse, {}, n},        {engine::RayKind::random, {}, n}};
    std::vector<accel::Ray> rays;
    for (const Set& s : sets) {
        engine::RayGenConfig cfg;
        cfg.kind = s.kind;
        cfg.count = s.count;
        cfg.seed = seed;
        cfg.shadow = s.shadow;
        const auto r = engine::generate_rays(gs, cfg, &tracer);
        rays.insert(rays.end(), r.begin(), r.end());
    }
    return rays;
}

/// `s` indices spread evenly over [0, n).
inline std::vector<std::size_t> spread(std::size_t n, std::size_t s) {
    std::vector<std::size_t> idx;
    for (std::size_t i = 0; i < std::min(n, s); ++i) idx.push_back(i * n / std::min(n, s));
    return idx;
}

}  // namespace arbor::testing
