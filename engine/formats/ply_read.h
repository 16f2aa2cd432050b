#pragma once
/// PLY values to a Mesh, read by arbor itself (ASCII, binary little and big endian): positions,
/// polygons (`face` lists), triangle strips (`tristrips` lists), `nx ny nz` normals, `red green
/// blue` colours (8-bit sRGB codes, made linear) and texture coordinates (`u v`, `s t`,
/// `texture_u texture_v`, `texture_s texture_t`). Nothing the file holds is dropped unsaid: data
/// that describes no surface (an `edge` or `material` element, a vertex's `confidence`, a face's
/// `flags`) is skipped with one warning naming it, and an element of vertex index lists that is not
/// read as surfaces is refused.
#include "engine/formats/ply_check.h"
#include "engine/log.h"
#include "engine/mesh.h"

#include <string>
#include <string_view>

namespace arbor::engine::formats {

struct PlyMesh {
    Mesh mesh;
    std::uint64_t point_line_faces = 0;  ///< faces of 1 or 2 vertices (no triangle)
};

/// Reads `bytes`, whose header is `header` and whose body check_ply_body has walked. Triangles are
/// numbered in the order of the elements in the file, then of their records: a face of k vertices
/// gives k - 2 triangles (engine/polygon.h), a strip list its triangles as
/// engine/formats/tristrip.h cuts them (the joints, triangles with a repeated vertex, get no
/// number). InputError naming `name` for: a vertex element without x, y or z, a second vertex
/// element, a face or tristrips element without a `vertex_indices` (or `vertex_index`) list, any
/// other element holding such a list, an index past the vertex list or negative (strips: below
/// -1), a value that is not a number, an index that is not an integer.
PlyMesh read_ply(const PlyHeader& header, std::string_view bytes, const std::string& name, Warnings& warnings);

}  // namespace arbor::engine::formats
