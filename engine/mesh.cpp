#include "engine/mesh.h"

namespace arbor::engine {

namespace {

/// Appends three corner indices to `index`, creating it (all no_attribute for the earlier
/// triangles) on the first corner that has one; does nothing while no triangle has any.
void add_corners(std::vector<std::uint32_t>& index, const std::uint32_t (&c)[3], std::size_t earlier_triangles) {
    const bool any = c[0] != no_attribute || c[1] != no_attribute || c[2] != no_attribute;
    if (index.empty() && !any) return;
    if (index.empty()) index.assign(3 * earlier_triangles, no_attribute);
    index.insert(index.end(), {c[0], c[1], c[2]});
}

/// Appends `other`'s corner indices shifted by `base` (no_attribute stays), padding whichever side
/// had none.
void append_corners(std::vector<std::uint32_t>& index, std::size_t own_triangles, const std::vector<std::uint32_t>& other,
                    std::size_t other_triangles, std::uint32_t base) {
    if (index.empty() && other.empty()) return;
    if (index.empty()) index.assign(3 * own_triangles, no_attribute);
    if (other.empty()) {
        index.insert(index.end(), 3 * other_triangles, no_attribute);
        return;
    }
    for (std::uint32_t i : other) index.push_back(i == no_attribute ? i : base + i);
}

}  // namespace

std::uint32_t Mesh::add_vertex(const Vec3f& p) {
    x.push_back(p.x);
    y.push_back(p.y);
    z.push_back(p.z);
    return std::uint32_t(x.size() - 1);
}

void Mesh::add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t mat) {
    indices.insert(indices.end(), {a, b, c});
    if (!material.empty() || mat != 0) {
        material.resize(triangle_count() - 1, 0);
        material.push_back(mat);
    }
    if (!normal_index.empty()) normal_index.insert(normal_index.end(), 3, no_attribute);
    if (!uv_index.empty()) uv_index.insert(uv_index.end(), 3, no_attribute);
}

void Mesh::add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t mat, const CornerAttributes& attr) {
    const std::size_t earlier = triangle_count();
    indices.insert(indices.end(), {a, b, c});
    if (!material.empty() || mat != 0) {
        material.resize(earlier, 0);
        material.push_back(mat);
    }
    add_corners(normal_index, attr.normal, earlier);
    add_corners(uv_index, attr.uv, earlier);
}

void Mesh::append(const Mesh& other) {
    const auto base = std::uint32_t(vertex_count());
    const std::size_t first_tri = triangle_count();
    if (!colors.empty() || !other.colors.empty()) {
        colors.resize(vertex_count(), Vec3f{1.0f});
        if (other.colors.empty()) colors.insert(colors.end(), other.vertex_count(), Vec3f{1.0f});
        else colors.insert(colors.end(), other.colors.begin(), other.colors.end());
    }
    x.insert(x.end(), other.x.begin(), other.x.end());
    y.insert(y.end(), other.y.begin(), other.y.end());
    z.insert(z.end(), other.z.begin(), other.z.end());
    for (std::uint32_t i : other.indices) indices.push_back(base + i);
    append_corners(normal_index, first_tri, other.normal_index, other.triangle_count(), std::uint32_t(normals.size()));
    normals.insert(normals.end(), other.normals.begin(), other.normals.end());
    append_corners(uv_index, first_tri, other.uv_index, other.triangle_count(), std::uint32_t(uvs.size()));
    uvs.insert(uvs.end(), other.uvs.begin(), other.uvs.end());
    // Materials become explicit per triangle once two meshes are merged.
    if (materials.empty()) materials.push_back(Material{});
    material.resize(first_tri, 0);
    const auto mat_base = std::uint32_t(materials.size());
    const int tex_base = int(textures.size());
    if (other.materials.empty()) materials.push_back(Material{});
    for (Material m : other.materials) {
        if (m.diffuse_texture >= 0) m.diffuse_texture += tex_base;
        materials.push_back(std::move(m));
    }
    textures.insert(textures.end(), other.textures.begin(), other.textures.end());
    for (std::size_t t = 0; t < other.triangle_count(); ++t)
        material.push_back(mat_base + (other.material.empty() ? 0 : other.material[t]));
    bounds.grow(other.bounds);
}

void Mesh::compute_bounds() {
    bounds = {};
    for (std::uint32_t i : indices) bounds.grow(Vec3f{x[i], y[i], z[i]});
}

std::uint64_t Mesh::bytes() const {
    std::uint64_t b = 4 * (x.size() + y.size() + z.size() + indices.size() + material.size() + normal_index.size() +
                           uv_index.size()) +
                      sizeof(Vec3f) * (normals.size() + colors.size()) + sizeof(Vec2f) * uvs.size();
    for (const Texture& t : textures) b += t.texels.size();
    return b;
}

}  // namespace arbor::engine
