#include "engine/mesh.h"

namespace arbor::engine {

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
}

void Mesh::append(const Mesh& other) {
    const auto base = std::uint32_t(vertex_count());
    const std::size_t first_tri = triangle_count();
    x.insert(x.end(), other.x.begin(), other.x.end());
    y.insert(y.end(), other.y.begin(), other.y.end());
    z.insert(z.end(), other.z.begin(), other.z.end());
    for (std::uint32_t i : other.indices) indices.push_back(base + i);
    // Materials become explicit per triangle once two meshes are merged.
    if (materials.empty()) materials.push_back(Material{});
    material.resize(first_tri, 0);
    const auto mat_base = std::uint32_t(materials.size());
    if (other.materials.empty()) materials.push_back(Material{});
    else materials.insert(materials.end(), other.materials.begin(), other.materials.end());
    for (std::size_t t = 0; t < other.triangle_count(); ++t)
        material.push_back(mat_base + (other.material.empty() ? 0 : other.material[t]));
    bounds.grow(other.bounds);
}

void Mesh::compute_bounds() {
    bounds = {};
    for (std::uint32_t i : indices) bounds.grow(Vec3f{x[i], y[i], z[i]});
}

}  // namespace arbor::engine
