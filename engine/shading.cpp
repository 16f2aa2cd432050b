#include "engine/shading.h"

#include <cmath>

namespace arbor::engine {

namespace {

/// Corner k's normal turned to ng's side, or ng for a corner without one.
Vec3f corner_normal(const Mesh& m, std::uint32_t prim, int k, const Vec3f& ng) {
    const std::uint32_t i = m.normal_index[3 * std::size_t(prim) + std::size_t(k)];
    if (i == no_attribute) return ng;
    const Vec3f n = m.normals[i];
    if (!(simd::dot(n, n) > 0.0f)) return ng;
    return simd::dot(n, ng) < 0.0f ? -n : n;
}

}  // namespace

Vec3f shading_normal(const Mesh& m, std::uint32_t prim, Barycentrics b, const Vec3f& ng) {
    const Vec3f n = corner_normal(m, prim, 0, ng) * b.b0 + corner_normal(m, prim, 1, ng) * b.b1 + corner_normal(m, prim, 2, ng) * b.b2;
    const float len = simd::length(n);
    if (!(len > 0.0f) || !std::isfinite(len)) return ng;
    const Vec3f ns = n / len;
    return simd::dot(ns, ng) > 0.0f ? ns : ng;
}

Vec3f terminator_point(const Mesh& m, std::uint32_t prim, Barycentrics b, const Vec3f& p, const Vec3f& ng) {
    const float w[3] = {b.b0, b.b1, b.b2};
    Vec3f lift{0.0f};
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t vi = m.indices[3 * std::size_t(prim) + std::size_t(k)];
        const Vec3f corner{m.x[vi], m.y[vi], m.z[vi]};
        const Vec3f n = corner_normal(m, prim, k, ng);
        // Below corner k's tangent plane by d: lift by d along n (Hanika 2021, listing 1).
        const float d = std::min(0.0f, simd::dot(p - corner, n));
        lift = lift - n * (d * w[k]);
    }
    const Vec3f q = p + lift;
    return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) ? q : p;
}

Vec3f albedo_at(const Mesh& m, const Material& mat, std::uint32_t prim, Barycentrics b, bool textures, bool colors) {
    Vec3f a = mat.diffuse;
    const std::size_t c0 = 3 * std::size_t(prim);
    if (textures && mat.diffuse_texture >= 0) {
        const std::uint32_t t0 = m.uv_index[c0], t1 = m.uv_index[c0 + 1], t2 = m.uv_index[c0 + 2];
        if (t0 != no_attribute && t1 != no_attribute && t2 != no_attribute) {
            const float u = m.uvs[t0].u * b.b0 + m.uvs[t1].u * b.b1 + m.uvs[t2].u * b.b2;
            const float v = m.uvs[t0].v * b.b0 + m.uvs[t1].v * b.b1 + m.uvs[t2].v * b.b2;
            a = a * m.textures[std::size_t(mat.diffuse_texture)].sample(u, v);
        }
    }
    if (colors) {
        const Vec3f c = m.colors[m.indices[c0]] * b.b0 + m.colors[m.indices[c0 + 1]] * b.b1 + m.colors[m.indices[c0 + 2]] * b.b2;
        a = a * c;
    }
    return a;
}

}  // namespace arbor::engine
