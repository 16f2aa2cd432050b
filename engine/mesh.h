#pragma once
/// Mesh: owned triangle data in structure-of-arrays form, the engine side of accel::TriangleView.
#include "accel/core/geometry.h"

#include <string>
#include <vector>

namespace arbor::engine {

using accel::Bounds;
using accel::Vec3f;

/// What the renderer needs of an MTL material (Kd, Ks as mirror, Ke); nothing else is read.
struct Material {
    std::string name = "default";
    Vec3f diffuse{0.8f, 0.8f, 0.8f};
    Vec3f mirror{0.0f, 0.0f, 0.0f};    ///< reflectance of a perfect mirror lobe
    Vec3f emission{0.0f, 0.0f, 0.0f};
};

struct Mesh {
    std::vector<float> x, y, z;              ///< vertex positions
    std::vector<std::uint32_t> indices;      ///< 3 per triangle, in the numbering of rayfile.md
    std::vector<std::uint32_t> material;     ///< per triangle, index into materials (may be empty: all 0)
    std::vector<Material> materials;         ///< at least one when material is non-empty
    Bounds bounds;                           ///< of the vertices used by triangles

    std::size_t triangle_count() const { return indices.size() / 3; }
    std::size_t vertex_count() const { return x.size(); }
    accel::TriangleView view() const { return {x, y, z, indices}; }

    std::uint32_t add_vertex(const Vec3f& p);
    void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t mat = 0);
    /// Appends `other` (indices and materials shifted).
    void append(const Mesh& other);
    void compute_bounds();
};

}  // namespace arbor::engine
