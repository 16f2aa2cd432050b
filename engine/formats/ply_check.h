#pragma once
/// PLY structure: the header, and a walk over the body's records (sizes only, no values) before
/// engine/formats/ply_read.h reads the values, so that a binary body cut short or an element count
/// larger than the file gets one clear error before anything is allocated for it.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace arbor::engine::formats {

/// A PLY scalar type (both the 1.0 names, e.g. `uchar`, and the sized ones, e.g. `uint8`).
enum class PlyType { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::float32;      ///< of a scalar, or of a list's items
    PlyType count_type = PlyType::uint8;  ///< of a list's count (lists only)
    int size = 0;        ///< bytes of a scalar, or of a list's items
    int count_size = 0;  ///< bytes of a list's count (0: not a list)
    bool count_signed = false;
};

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> properties;
};

struct PlyHeader {
    enum class Encoding { ascii, binary_little_endian, binary_big_endian } encoding = Encoding::ascii;
    std::vector<PlyElement> elements;
    std::size_t body_offset = 0;  ///< first byte after "end_header" and its line break
    /// One line each ("NAME:LINE: ..."): header lines that are no keyword and carry no data, such
    /// as Blender's "Created by Blender3D 247 - www.blender.org, source file: 'x.blend'".
    std::vector<std::string> warnings;
};

/// True when `bytes` starts like a PLY file ("ply" and a line break).
bool looks_like_ply(std::string_view bytes);

/// Parses the header; InputError naming `name` for anything malformed (unknown format or type, a
/// property outside an element, no end_header). A line whose first word is no PLY keyword is
/// skipped with a warning (header.warnings), as Assimp and other readers skip it.
PlyHeader parse_ply_header(std::string_view bytes, const std::string& name);

/// Walks the body: every record of every element must be there (binary: inside the file; ASCII:
/// enough numbers). InputError naming the element and record where the data runs out, or, before
/// any walking, the element whose count alone needs more bytes than the file has.
void check_ply_body(const PlyHeader& header, std::string_view bytes, const std::string& name);

}  // namespace arbor::engine::formats
