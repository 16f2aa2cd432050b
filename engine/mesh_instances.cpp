#include "engine/mesh_instances.h"

#include <algorithm>

#include "accel/factory/make_accel.h"
#include "accel/instances/instance_accel.h"
#include "engine/error.h"

namespace arbor::engine {

namespace {

/// The vertices triangles [first, first + count) use, each once, in first-use order.
std::vector<std::uint32_t> used_vertices(const Mesh& m, std::uint32_t first, std::uint32_t count) {
    std::vector<std::uint32_t> out;
    std::vector<char> seen(m.vertex_count(), 0);
    for (std::size_t k = 3 * std::size_t(first); k < 3 * (std::size_t(first) + count); ++k)
        if (!seen[m.indices[k]]) seen[m.indices[k]] = 1, out.push_back(m.indices[k]);
    return out;
}

/// p carried by `a` in double and rounded once (untouched for no transform).
Vec3f carry(const accel::Affine* a, float x, float y, float z) {
    if (!a) return {x, y, z};
    const auto p = a->point(x, y, z);
    return {float(p[0]), float(p[1]), float(p[2])};
}

/// Calls f(first, count, transform or null) for every placement, in numbering order.
template <class F>
void each_placement(const MeshInstances& inst, F&& f) {
    if (inst.drawn > 0) f(0u, inst.drawn, static_cast<const accel::Affine*>(nullptr));
    for (const PartInstance& i : inst.instances) f(inst.parts[i.part].first, inst.parts[i.part].count, &i.transform);
}

/// Triangles [first, first + count) of `m` as a mesh of their own (vertex numbers from 0).
std::unique_ptr<accel::InstanceMesh> part_copy(const Mesh& m, std::uint32_t first, std::uint32_t count) {
    auto out = std::make_unique<accel::InstanceMesh>();
    std::vector<std::uint32_t> remap(m.vertex_count(), no_attribute);
    out->indices.reserve(3 * std::size_t(count));
    for (std::size_t k = 3 * std::size_t(first); k < 3 * (std::size_t(first) + count); ++k) {
        const std::uint32_t v = m.indices[k];
        if (remap[v] == no_attribute) {
            remap[v] = std::uint32_t(out->x.size());
            out->x.push_back(m.x[v]), out->y.push_back(m.y[v]), out->z.push_back(m.z[v]);
        }
        out->indices.push_back(remap[v]);
    }
    const accel::TriangleView v = out->view();
    for (std::size_t t = 0; t < v.triangle_count(); ++t)
        if (v.triangle_is_finite(t)) out->bounds.grow(v.triangle_bounds(t));
    return out;
}

}  // namespace

void MeshInstances::index(const Mesh& mesh, const std::string& name) {
    std::uint64_t end = drawn;
    if (drawn > mesh.triangle_count()) throw InputError(name, 0, "instances: the drawn triangles exceed the mesh");
    for (std::size_t p = 0; p < parts.size(); ++p) {
        if (parts[p].first < end || std::uint64_t(parts[p].first) + parts[p].count > mesh.triangle_count())
            throw InputError(name, 0,
                             "instances: part " + std::to_string(p) + " overlaps another or lies outside the mesh");
        end = std::uint64_t(parts[p].first) + parts[p].count;
    }
    first.assign(instances.size(), 0);
    std::uint64_t next = drawn;
    for (std::size_t k = 0; k < instances.size(); ++k) {
        if (instances[k].part >= parts.size())
            throw InputError(name, 0,
                             "instances: instance " + std::to_string(k) + " names part " +
                                 std::to_string(instances[k].part) + " of " + std::to_string(parts.size()));
        const std::string problem = accel::check_affine(instances[k].transform);
        if (!problem.empty()) throw InputError(name, 0, "instance " + std::to_string(k) + ": transform: " + problem);
        first[k] = next;
        next += parts[instances[k].part].count;
        if (next >= accel::invalid_prim)
            throw InputError(name, 0,
                             "instances: the placed triangles number 2^32 - 1 or more (" + std::to_string(next) +
                                 " by instance " + std::to_string(k) + ")");
    }
}

std::uint64_t MeshInstances::effective_triangles() const {
    std::uint64_t n = drawn;
    for (const PartInstance& i : instances) n += parts[i.part].count;
    return n;
}

std::uint64_t MeshInstances::effective(std::uint64_t held, std::uint32_t MeshPart::*field) const {
    std::uint64_t n = held;
    for (const MeshPart& p : parts) n -= p.*field;
    for (const PartInstance& i : instances) n += parts[i.part].*field;
    return n;
}

PlacedPrim MeshInstances::locate(std::uint32_t global) const {
    if (instances.empty() || global < drawn) return {global, nullptr};
    const auto it = std::upper_bound(first.begin(), first.end(), std::uint64_t(global));
    const std::size_t k = std::size_t(it - first.begin()) - 1;
    const PartInstance& i = instances[k];
    return {parts[i.part].first + std::uint32_t(global - first[k]), &i.transform};
}

accel::Bounds world_bounds(const Mesh& mesh, const MeshInstances& inst, bool exact) {
    if (inst.empty()) return mesh.bounds;
    accel::Bounds out;
    std::vector<std::vector<std::uint32_t>> used(inst.parts.size());
    std::vector<accel::Bounds> box(inst.parts.size());
    for (std::size_t p = 0; p < inst.parts.size(); ++p) {
        used[p] = used_vertices(mesh, inst.parts[p].first, inst.parts[p].count);
        for (std::uint32_t v : used[p]) box[p].grow(Vec3f{mesh.x[v], mesh.y[v], mesh.z[v]});
    }
    for (std::uint32_t v : used_vertices(mesh, 0, inst.drawn)) out.grow(Vec3f{mesh.x[v], mesh.y[v], mesh.z[v]});
    for (const PartInstance& i : inst.instances) {
        if (!exact) {
            out.grow(accel::transform_bounds(i.transform, box[i.part]));
            continue;
        }
        for (std::uint32_t v : used[i.part]) out.grow(carry(&i.transform, mesh.x[v], mesh.y[v], mesh.z[v]));
    }
    return out;
}

std::uint64_t flatten_bytes(const Mesh& mesh, const MeshInstances& inst) {
    if (inst.empty()) return mesh.bytes();
    const double per_tri = mesh.triangle_count() ? double(mesh.bytes()) / double(mesh.triangle_count()) : 0.0;
    return std::uint64_t(per_tri * double(inst.effective_triangles()));
}

Mesh flatten(const Mesh& m, const MeshInstances& inst) {
    if (inst.empty()) return m;
    Mesh out;
    out.materials = m.materials, out.textures = m.textures, out.uvs = m.uvs;
    const bool mats = !m.material.empty(), normals = m.has_normals(), uvs = m.has_uvs(), colors = !m.colors.empty();
    std::vector<std::uint32_t> vmap(m.vertex_count(), no_attribute), nmap(m.normals.size(), no_attribute);
    std::vector<std::uint32_t> touched_v, touched_n;
    each_placement(inst, [&](std::uint32_t first, std::uint32_t count, const accel::Affine* a) {
        const accel::Affine inv = a ? a->inverse() : accel::Affine{};
        for (std::size_t t = first; t < std::size_t(first) + count; ++t) {
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t v = m.indices[3 * t + std::size_t(c)];
                if (vmap[v] == no_attribute) {
                    vmap[v] = out.add_vertex(carry(a, m.x[v], m.y[v], m.z[v]));
                    if (colors) out.colors.push_back(m.colors[v]);
                    touched_v.push_back(v);
                }
                out.indices.push_back(vmap[v]);
                if (normals) {
                    const std::uint32_t n = m.normal_index[3 * t + std::size_t(c)];
                    if (n != no_attribute && nmap[n] == no_attribute) {
                        Vec3f w = m.normals[n];
                        if (a) {  // the inverse transpose, renormalized
                            const Vec3f o = m.normals[n];
                            for (int r = 0; r < 3; ++r)
                                w[r] = float(inv.at(0, r) * o.x + inv.at(1, r) * o.y + inv.at(2, r) * o.z);
                            const float len = simd::length(w);
                            w = len > 0.0f && std::isfinite(len) ? w / len : Vec3f{0.0f};
                        }
                        nmap[n] = std::uint32_t(out.normals.size());
                        out.normals.push_back(w);
                        touched_n.push_back(n);
                    }
                    out.normal_index.push_back(n == no_attribute ? n : nmap[n]);
                }
                if (uvs) out.uv_index.push_back(m.uv_index[3 * t + std::size_t(c)]);
            }
            if (mats) out.material.push_back(m.material[t]);
        }
        for (std::uint32_t v : touched_v) vmap[v] = no_attribute;
        for (std::uint32_t n : touched_n) nmap[n] = no_attribute;
        touched_v.clear(), touched_n.clear();
    });
    if (!normals) out.normals.clear();
    out.compute_bounds();
    return out;
}

std::unique_ptr<accel::Accel> make_instanced_accel(const Mesh& mesh, const MeshInstances& inst, accel::AccelKind kind,
                                                   const accel::BuildConfig& cfg) {
    if (kind == accel::AccelKind::automatic) kind = accel::AccelKind::bvh_sah;
    std::vector<accel::Bottom> bottoms(inst.parts.size() + 1);
    for (std::size_t p = 0; p <= inst.parts.size(); ++p) {
        const bool as_is = p == inst.parts.size();
        if (as_is && inst.drawn == 0) continue;
        bottoms[p].mesh =
            as_is ? part_copy(mesh, 0, inst.drawn) : part_copy(mesh, inst.parts[p].first, inst.parts[p].count);
        bottoms[p].accel = accel::make_accel(kind, bottoms[p].mesh->view(), cfg);
    }
    std::vector<accel::Placement> placements;
    placements.reserve(inst.instances.size() + 1);
    if (inst.drawn > 0)
        placements.push_back(
            accel::Placement::make(std::uint32_t(inst.parts.size()), accel::invalid_prim, accel::Affine{}));
    for (std::size_t k = 0; k < inst.instances.size(); ++k)
        placements.push_back(
            accel::Placement::make(inst.instances[k].part, std::uint32_t(k), inst.instances[k].transform));
    return std::make_unique<accel::InstanceAccel>(kind, std::move(bottoms), std::move(placements));
}

}  // namespace arbor::engine
