/// arbor::Scene::hit_normals: the geometric normal of each hit's triangle, from the scene's own
/// copy of the vertices.
#include <cmath>
#include <cstring>

#include "api/batch.h"
#include "api/scene_impl.h"

namespace arbor {

namespace {

constexpr std::size_t normal_chunk = 4096;

/// (v1-v0) x (v2-v0) of triangle `t`, normalized; zeros for a triangle of zero area. The edges and
/// the cross product are taken in double, so the direction of a thin triangle is not lost to
/// cancellation before it is rounded once to float.
void unit_normal(const engine::Mesh& m, std::size_t t, float n[3]) {
    const std::uint32_t* v = &m.indices[3 * t];
    const double e1[3] = {double(m.x[v[1]]) - m.x[v[0]], double(m.y[v[1]]) - m.y[v[0]], double(m.z[v[1]]) - m.z[v[0]]};
    const double e2[3] = {double(m.x[v[2]]) - m.x[v[0]], double(m.y[v[2]]) - m.y[v[0]], double(m.z[v[2]]) - m.z[v[0]]};
    const double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double len = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    for (int k = 0; k < 3; ++k) n[k] = len > 0.0 && std::isfinite(len) ? float(c[k] / len) : 0.0f;
}

/// An object-space unit normal carried to world space by the cofactor matrix of A, det(A) A^-T:
/// the normal of the placed triangle, (A e1) x (A e2), so a mirroring A turns it over.
void to_world(const accel::Affine& a, float n[3]) {
    const accel::Affine inv = a.inverse();
    const double det = a.det();
    double w[3];
    for (int i = 0; i < 3; ++i) w[i] = det * (inv.at(0, i) * n[0] + inv.at(1, i) * n[1] + inv.at(2, i) * n[2]);
    const double len = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    for (int k = 0; k < 3; ++k) n[k] = len > 0.0 && std::isfinite(len) ? float(w[k] / len) : 0.0f;
}

}  // namespace

void Scene::hit_normals(const Hit* hits, std::size_t count, std::size_t hit_stride, float* normals,
                        std::size_t normal_stride, const QueryOptions& options) const {
    guarded([&] {
        using Kind = Error::Kind;
        CallArena arena(*impl_, options, "hit_normals");
        if (count == 0) return;
        if (!hits || !normals)
            throw Error(Kind::invalid_argument,
                        std::string("hit_normals: ") + (hits ? "normals" : "hits") + " is null");
        const auto* in = reinterpret_cast<const unsigned char*>(hits);
        auto* out = reinterpret_cast<unsigned char*>(normals);
        const auto hit_at = [&](std::size_t i) {
            Hit h;
            std::memcpy(&h, in + i * hit_stride, sizeof h);  // any stride, any alignment
            return h;
        };
        // Every id checked before anything is written: an error leaves `normals` as it was.
        const Impl& s = *impl_;
        for (std::size_t i = 0; i < count; ++i) {
            const Hit h = hit_at(i);
            if (h.prim == invalid_id) continue;
            const std::size_t meshes = s.first_prim.size();
            const std::size_t first = h.geom < meshes ? s.first_prim[h.geom] : 0;
            const std::size_t end = h.geom + 1 < meshes ? s.first_prim[h.geom + 1] : s.mesh.triangle_count();
            if (h.geom >= meshes || h.prim >= end - first)
                throw Error(Kind::invalid_argument, "hit_normals: hit " + std::to_string(i) + " names geom " +
                                                        std::to_string(h.geom) + ", prim " + std::to_string(h.prim) +
                                                        ", which the scene does not hold");
            if (h.inst != invalid_id && (h.inst >= s.instances.size() || s.instances[h.inst].geom != h.geom))
                throw Error(Kind::invalid_argument, "hit_normals: hit " + std::to_string(i) + " names instance " +
                                                        std::to_string(h.inst) + " of geom " + std::to_string(h.geom) +
                                                        ", which the scene does not hold");
        }
        for_chunks(arena, count, normal_chunk, [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) {
                const Hit h = hit_at(i);
                float n[3] = {0.0f, 0.0f, 0.0f};
                if (h.prim != invalid_id) unit_normal(s.mesh, s.first_prim[h.geom] + h.prim, n);
                if (h.prim != invalid_id && h.inst != invalid_id) to_world(s.instances[h.inst].transform, n);
                std::memcpy(out + i * normal_stride, n, sizeof n);
            }
        }, /*counted=*/false);
    });
}

}  // namespace arbor
