#pragma once
/// The public API tests' scene: an icosphere (geom 0) and a torus (geom 1), the two concatenated
/// for the engine's brute-force oracle, and the conversions between the public and engine records.
#include "accel/core/ray.h"
#include "engine/mesh.h"
#include "engine/procedural.h"

#include <arbor/arbor.h>

#include <cstring>
#include <vector>

namespace arbor::testing {

struct TwoMeshes {
    engine::Mesh sphere = engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.05f, 2);
    engine::Mesh torus = engine::make_torus({2.5f, 0, 0}, 1.0f, 0.3f, 24, 12);
    engine::Mesh both;  ///< sphere then torus: the oracle's prims run over both

    TwoMeshes() {
        both = sphere;
        both.append(torus);
        both.compute_bounds();
    }
    const engine::Mesh& mesh(std::uint32_t geom) const { return geom == 0 ? sphere : torus; }

    /// A mesh's positions as a program's packed x, y, z array.
    static std::vector<float> positions(const engine::Mesh& m) {
        std::vector<float> p;
        for (std::size_t i = 0; i < m.vertex_count(); ++i) p.insert(p.end(), {m.x[i], m.y[i], m.z[i]});
        return p;
    }
    /// Adds the two meshes to `s` from packed arrays (geom 0 and 1).
    void add_to(Scene& s) const {
        s.add_mesh(positions(sphere), sphere.indices);
        s.add_mesh(positions(torus), torus.indices);
    }
    /// The public hit the oracle's hit (a prim over both meshes) maps to.
    Hit map(const accel::Hit& h) const {
        Hit out;
        if (!h.is_hit()) return out;
        const auto n0 = std::uint32_t(sphere.triangle_count());
        out.geom = h.prim < n0 ? 0 : 1;
        out.prim = h.prim < n0 ? h.prim : h.prim - n0;
        out.t = h.t, out.u = h.u, out.v = h.v;
        return out;
    }
};

/// Engine rays as public rays (the same 32-byte records).
inline std::vector<Ray> to_public(const std::vector<accel::Ray>& rays) {
    static_assert(sizeof(Ray) == sizeof(accel::Ray));
    std::vector<Ray> out(rays.size());
    std::memcpy(static_cast<void*>(out.data()), rays.data(), rays.size() * sizeof(accel::Ray));
    return out;
}

}  // namespace arbor::testing
