#include "engine/mesh_validate.h"

#include "engine/error.h"

#include <cmath>
#include <cstdio>

namespace arbor::engine {

namespace {

void check_index(const std::vector<std::uint32_t>& index, std::size_t count, const char* what, const std::string& name) {
    for (std::size_t k = 0; k < index.size(); ++k)
        if (index[k] != no_attribute && index[k] >= count)
            throw InputError(name, 0, "triangle " + std::to_string(k / 3) + " refers to " + what + " " + std::to_string(index[k]) +
                                          ", past the " + std::to_string(count) + " " + what + "s");
}

}  // namespace

void validate_mesh(Mesh& m, const std::string& name, const std::string& no_triangles_why) {
    std::size_t bad = 0, first = 0;
    for (std::size_t v = 0; v < m.vertex_count(); ++v)
        if (!std::isfinite(m.x[v]) || !std::isfinite(m.y[v]) || !std::isfinite(m.z[v])) {
            if (bad++ == 0) first = v;
        }
    if (bad) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "%zu of %zu vertices %s not finite (the first: vertex %zu = %g %g %g)", bad,
                      m.vertex_count(), bad == 1 ? "is" : "are", first, double(m.x[first]), double(m.y[first]), double(m.z[first]));
        throw InputError(name, 0, buf);
    }
    if (m.triangle_count() == 0) throw InputError(name, 0, "no triangles" + no_triangles_why);
    check_index(m.indices, m.vertex_count(), "vertex", name);
    if (m.has_normals() && m.normal_index.size() != m.indices.size()) throw InputError(name, 0, "normal indices do not match the triangles");
    if (m.has_uvs() && m.uv_index.size() != m.indices.size()) throw InputError(name, 0, "texture coordinate indices do not match the triangles");
    check_index(m.normal_index, m.normals.size(), "normal", name);
    check_index(m.uv_index, m.uvs.size(), "texture coordinate", name);
    if (!m.colors.empty() && m.colors.size() != m.vertex_count()) throw InputError(name, 0, "vertex colours do not match the vertices");
    if (!m.material.empty() && m.material.size() != m.triangle_count()) throw InputError(name, 0, "materials do not match the triangles");
    for (std::uint32_t id : m.material)
        if (id >= m.materials.size()) throw InputError(name, 0, "a triangle refers to material " + std::to_string(id) + ", past the materials");
    for (const Material& mat : m.materials)
        if (mat.diffuse_texture >= int(m.textures.size())) throw InputError(name, 0, "a material refers to a missing texture");
    m.compute_bounds();
}

}  // namespace arbor::engine
