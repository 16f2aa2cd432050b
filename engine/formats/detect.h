#pragma once
/// Which format a mesh file is in, told by its bytes: "ply" + line break, the GLB magic "glTF", a
/// JSON object with glTF's asset, a binary STL (84-byte header whose triangle count matches the
/// size exactly) or an ASCII STL ("solid" ... "facet"); anything else is read as OBJ text. The
/// extension decides only where the content says nothing (a binary STL whose size does not match
/// its count is still reported as a broken STL when it is named .stl).
#include <cstdint>
#include <string>
#include <string_view>

namespace arbor::engine::formats {

enum class MeshFormat { obj, ply, stl_ascii, stl_binary, gltf, glb };

/// "OBJ", "PLY", "STL", "glTF", "GLB": for messages and `arbor info`.
const char* format_name(MeshFormat f);

MeshFormat detect_mesh_format(std::string_view bytes, const std::string& path);

/// A binary STL's triangle count from its header, or -1 when the file is shorter than 84 bytes.
long long stl_binary_count(std::string_view bytes);

/// InputError naming `name` when `bytes` is not a complete binary STL (size = 84 + 50 x count).
void check_stl_binary(std::string_view bytes, const std::string& name);

}  // namespace arbor::engine::formats
