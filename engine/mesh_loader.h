#pragma once
/// The one entry for mesh files of every format arbor reads: OBJ (tinyobjloader plus arbor's own
/// line checks, engine/obj_loader.h), PLY (ASCII and binary of either byte order, read by arbor:
/// engine/formats/ply_read.h), STL (ASCII and binary) and glTF 2.0 (.gltf, .glb) through Assimp
/// (engine/formats/). The format is told by the
/// file's content (engine/formats/detect.h), not only by its name. Every format ends in the same
/// validation (engine/mesh_validate.h) and the same one-line "FILE: problem" errors.
#include "engine/formats/detect.h"
#include "engine/log.h"
#include "engine/mesh.h"
#include "engine/mesh_instances.h"

#include <cstdint>
#include <string>
#include <string_view>

namespace arbor::engine {

using formats::MeshFormat;

/// Loads `path` in whatever supported format it holds. Before reading, a file whose loading would
/// need more than `max_bytes` (mesh_load_bytes; 0: the machine's physical memory) is refused.
/// Throws InputError ("FILE: problem", OBJ: "FILE:LINE: problem").
/// Node transforms are applied (a flat mesh) unless `instances` is given: then a glTF file whose
/// nodes place a mesh more than once comes back as its meshes once each and `instances` placing
/// them (indexed; formats/assimp_import.h says when), other files as before with `instances` empty.
Mesh load_mesh(const std::string& path, Warnings& warnings, std::uint64_t max_bytes = 0, MeshFormat* format = nullptr,
               MeshInstances* instances = nullptr);

/// Same, from a file's bytes already in memory; `name` is used in messages and `base_dir` (ending
/// in '/', or empty for the current folder) to find the files it names (MTL, textures, glTF
/// buffers). `read_other_files` false: nothing but `bytes` is read (the fuzzers).
Mesh load_mesh_bytes(std::string_view bytes, const std::string& name, const std::string& base_dir, Warnings& warnings,
                     bool read_other_files = true, MeshFormat* format = nullptr, MeshInstances* instances = nullptr);

/// Bytes loading a file of `file_bytes` bytes in `format` needs, about (the text or bytes, the
/// reader's own copy, the mesh): 3x for OBJ, 8x for the formats read through Assimp.
std::uint64_t mesh_load_bytes(MeshFormat format, std::uint64_t file_bytes);

}  // namespace arbor::engine
