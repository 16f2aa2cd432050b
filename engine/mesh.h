#pragma once
/// Mesh: owned triangle data in structure-of-arrays form, the engine side of accel::TriangleView,
/// with the optional shading attributes that the renderer reads only when its plan needs them.
#include "accel/core/geometry.h"
#include "engine/texture.h"

#include <cstdint>
#include <string>
#include <vector>

namespace arbor::engine {

using accel::Bounds;
using accel::Vec3f;

/// What the renderer needs of a material (MTL Kd, Ks as mirror, Ke, map_Kd; glTF base colour and
/// its texture); nothing else is read.
struct Material {
    std::string name = "default";
    Vec3f diffuse{0.8f, 0.8f, 0.8f};
    Vec3f mirror{0.0f, 0.0f, 0.0f};    ///< reflectance of a perfect mirror lobe
    Vec3f emission{0.0f, 0.0f, 0.0f};
    int diffuse_texture = -1;          ///< index into Mesh::textures, multiplies `diffuse`; -1: none
};

/// A corner attribute index meaning "this corner has none" (flat normal, no texture coordinate).
inline constexpr std::uint32_t no_attribute = 0xFFFFFFFFu;

/// Attribute indices of a triangle's three corners (no_attribute where the file gives none).
struct CornerAttributes {
    std::uint32_t normal[3] = {no_attribute, no_attribute, no_attribute};
    std::uint32_t uv[3] = {no_attribute, no_attribute, no_attribute};
};

struct Mesh {
    std::vector<float> x, y, z;              ///< vertex positions
    std::vector<std::uint32_t> indices;      ///< 3 per triangle, in the numbering of rayfile.md
    std::vector<std::uint32_t> material;     ///< per triangle, index into materials (may be empty: all 0)
    std::vector<Material> materials;         ///< at least one when material is non-empty
    Bounds bounds;                           ///< of the vertices used by triangles

    /// Vertex normals (unit length) and their per-corner indices, 3 per triangle (no_attribute:
    /// that corner is flat). Both empty when no triangle has any.
    std::vector<Vec3f> normals;
    std::vector<std::uint32_t> normal_index;
    /// Texture coordinates (u, v with v = 0 at the image's bottom, as OBJ and OpenGL have it) and
    /// their per-corner indices, as for the normals.
    std::vector<Vec2f> uvs;
    std::vector<std::uint32_t> uv_index;
    /// Per-vertex colours (same indices as the positions; multiply the diffuse colour); may be empty.
    std::vector<Vec3f> colors;
    /// Decoded images that materials refer to by index.
    std::vector<Texture> textures;

    std::size_t triangle_count() const { return indices.size() / 3; }
    std::size_t vertex_count() const { return x.size(); }
    accel::TriangleView view() const { return {x, y, z, indices}; }
    bool has_normals() const { return !normal_index.empty(); }
    bool has_uvs() const { return !uv_index.empty(); }

    std::uint32_t add_vertex(const Vec3f& p);
    void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t mat = 0);
    /// Same, with the corners' normal and texture-coordinate indices.
    void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t mat, const CornerAttributes& attr);
    /// Appends `other` (indices, materials, attributes and textures shifted).
    void append(const Mesh& other);
    void compute_bounds();
    /// Bytes held by the arrays (for memory estimates and `arbor info`).
    std::uint64_t bytes() const;
};

}  // namespace arbor::engine
