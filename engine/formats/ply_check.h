#pragma once
/// PLY structure checks before Assimp reads a file. Assimp 5.2's PLY reader trusts the header: a
/// binary body cut short is read past its end (garbage indices), and an element count larger than
/// the file makes it allocate and loop for minutes. arbor reads the header itself and walks the
/// body's records (sizes only, no values), so that such files get one clear error first.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace arbor::engine::formats {

struct PlyProperty {
    std::string name;
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
};

/// True when `bytes` starts like a PLY file ("ply" and a line break).
bool looks_like_ply(std::string_view bytes);

/// Parses the header; InputError naming `name` for anything malformed (unknown format, type or
/// keyword, a property outside an element, no end_header).
PlyHeader parse_ply_header(std::string_view bytes, const std::string& name);

/// Walks the body: every record of every element must be there (binary: inside the file; ASCII:
/// enough numbers). InputError naming the element and record where the data runs out, or, before
/// any walking, the element whose count alone needs more bytes than the file has.
void check_ply_body(const PlyHeader& header, std::string_view bytes, const std::string& name);

}  // namespace arbor::engine::formats
