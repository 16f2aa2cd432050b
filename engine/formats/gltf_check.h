#pragma once
/// glTF 2.0 structure checks around Assimp. Before: the GLB container (header, chunk lengths
/// inside the file) and the JSON (it must parse). After: Assimp 5.2 silently drops a triangle
/// whose index points past its primitive's vertices, so the triangles each primitive must give
/// (from the accessors' counts and the primitive's mode) are counted here and compared with what
/// Assimp returned.
#include <cstdint>
#include <string>
#include <string_view>

namespace arbor::engine::formats {

/// True for a binary glTF (magic "glTF").
bool looks_like_glb(std::string_view bytes);
/// True for a JSON text whose first non-blank byte is '{' (a .gltf, or some other JSON).
bool looks_like_json(std::string_view bytes);

struct GltfCounts {
    std::uint64_t triangles = 0;        ///< triangles the file's primitives define (each mesh once)
    std::uint64_t point_line_prims = 0;  ///< primitives of points or lines
    std::string first_point_line;        ///< the first of them, e.g. "meshes[0].primitives[1] (mode 1: lines)"
};

/// Checks the container and the JSON and counts the triangles; InputError naming `name` for a
/// truncated or inconsistent GLB, JSON that does not parse, a version other than 2.x, or
/// accessor references out of range.
GltfCounts check_gltf(std::string_view bytes, const std::string& name);

}  // namespace arbor::engine::formats
