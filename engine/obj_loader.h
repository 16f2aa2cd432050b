#pragma once
/// Wavefront OBJ loading. tinyobjloader walks the file and reads MTL libraries; every `v` and `f`
/// line is re-checked here, because tinyobjloader reads "nan" as 0, accepts index 0 and
/// out-of-range indices with at most a warning, and does not report line numbers.
#include "engine/log.h"
#include "engine/mesh.h"

#include <string>

namespace arbor::engine {

/// Loads `path`. Polygons become triangles in file order exactly as spec/rayfile.md numbers them
/// (convex ones fanned, others cut by ear clipping: engine/polygon.h); faces with fewer than 3
/// vertices are skipped with a warning, and so, in one warning naming them, are points (`p`), lines
/// (`l`) and free-form curves (`curv`, `curv2`): they are no surfaces. Numbers may carry a sign
/// (`v +1 -2 +3.0`). Normals (`vn`) and texture coordinates (`vt`) are kept with their per-corner
/// indices, `v x y z r g b` colours per vertex. Throws InputError ("FILE:LINE: problem") for
/// unreadable or binary files, malformed numbers or face tokens, non-finite coordinates, indices
/// out of range (1-based, negative = relative; also for vt and vn), free-form surfaces (`surf`,
/// not read), and files without a triangle. Non-fatal problems (missing MTL file; material colours out of range, which are
/// clamped: Kd and Ks to [0, 1], Ke to [0, max], non-finite values to 0) are added to `warnings`.
/// MTL: Kd is the diffuse colour, Ks the mirror reflectance when illum is 3..7, Ke the emission,
/// map_Kd a diffuse texture (decoded by stb_image; a missing or broken image is a warning).
/// Before reading, a file whose loading would need more than `max_bytes` (about 3x its size: the text, its line
/// index and the mesh; 0: the machine's physical memory) is refused with InputError.
Mesh load_obj(const std::string& path, Warnings& warnings, std::uint64_t max_bytes = 0);

/// Bytes load_obj needs, about, for a file of `file_bytes` bytes.
std::uint64_t obj_load_bytes(std::uint64_t file_bytes);

/// Same, from text already in memory; `name` is used in messages and `base_dir` to find MTL files.
Mesh load_obj_text(const std::string& text, const std::string& name, const std::string& base_dir,
                   Warnings& warnings);

}  // namespace arbor::engine
