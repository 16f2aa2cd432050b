#pragma once
/// STL and glTF 2.0 through Assimp (Debian libassimp-dev, 5.2); PLY is read by arbor itself
/// (ply_read.h), as Assimp 5.2's PLY reader makes one triangle of each `tristrips` list. Assimp is
/// given the file's bytes from memory under a name with the extension of the format arbor detected
/// (so the content, not the file name, picks the reader); other files a glTF names (.bin buffers,
/// images) are read from `base_dir`. No post-processing is asked for: arbor triangulates polygons itself, as
/// spec/rayfile.md numbers them, and applies node transforms itself (glTF: meshes in node order,
/// depth first). Values are not validated here (engine/mesh_validate.h does that for every format).
#include "engine/formats/detect.h"
#include "engine/log.h"
#include "engine/mesh.h"
#include "engine/mesh_instances.h"

#include <string>
#include <string_view>

namespace arbor::engine::formats {

/// What Assimp returned, each mesh counted once however many nodes use it: for the "only
/// points/lines" message and the check of glTF's triangle count (gltf_check.h).
struct ImportCounts {
    std::uint64_t point_line_faces = 0;  ///< faces with 1 or 2 indices
    std::uint64_t polygons = 0;          ///< faces with 3 or more indices
    std::uint64_t vertices = 0;
};

/// InputError "NAME: <format>: <Assimp's message>" when Assimp cannot read the file, and
/// "NAME: face F refers to vertex I, past the N vertices of its mesh" for an index out of range.
/// With `instances` (glTF only), a file whose nodes place some mesh more than once, every
/// transform invertible, comes back as each mesh once (a part, in the order the nodes first
/// use it) and one instance per (node, mesh) pair in node order, depth first, so that the
/// triangles are numbered as the flattened file numbers them; other files come back flattened
/// and `instances` empty.
Mesh import_with_assimp(std::string_view bytes, MeshFormat format, const std::string& name, const std::string& base_dir,
                        Warnings& warnings, ImportCounts& counts, MeshInstances* instances = nullptr);

}  // namespace arbor::engine::formats
