#pragma once
/// Writers of the mesh formats arbor reads, for the loading benchmark (`arbor-bench load`) and the loader
/// tests, which build their files themselves: PLY (ASCII, binary of either byte order), STL (ASCII,
/// binary), glTF 2.0 (.gltf with a data URI or an external buffer, .glb), OBJ text. Triangles are
/// written in order, so a file read back numbers them as the mesh does.
#include "engine/mesh.h"

#include <array>
#include <string>

namespace arbor::perf {

enum class PlyEncoding { ascii, binary_little_endian, binary_big_endian };

/// PLY with x y z, and nx ny nz / red green blue (uchar) per vertex when asked and present.
std::string ply_bytes(const engine::Mesh& m, PlyEncoding encoding, bool normals = false, bool colors = false);
/// STL; binary: 80-byte header, count, 50-byte records with the facet normal.
std::string stl_bytes(const engine::Mesh& m, bool binary);
/// OBJ text (v and f lines; vn, vt and v//vn-style corners when the mesh has them).
std::string obj_text(const engine::Mesh& m);

struct GltfOptions {
    bool binary = true;            ///< .glb; false: .gltf JSON
    bool normals = true;           ///< write per-vertex normals when the mesh has them (corner = vertex index)
    bool uvs = true;               ///< same for texture coordinates (written with glTF's v flipped: 1 - v)
    std::string png;               ///< an image for the base colour texture (embedded), or empty
    std::array<float, 3> base_color{1.0f, 1.0f, 1.0f};
    std::array<float, 16> matrix{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  ///< the node's, column-major
    std::string external_buffer;   ///< .gltf only: name of a .bin file the buffer goes to (returned in *bin)
};

/// One mesh, one primitive, one node. With `external_buffer` set, the buffer's bytes are put in
/// *bin for the caller to write beside the .gltf.
std::string gltf_bytes(const engine::Mesh& m, const GltfOptions& options, std::string* bin = nullptr);

/// An 8-bit RGB PNG of `width` x `height` pixels (rgb: rows top to bottom), for texture tests.
std::string png_bytes(int width, int height, const std::vector<std::uint8_t>& rgb);

/// `m` copied `copies` times side by side along x (each copy shifted by 1.1 of the mesh's width).
engine::Mesh replicate(const engine::Mesh& m, int copies);

}  // namespace arbor::perf
