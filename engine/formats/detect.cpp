#include "engine/formats/detect.h"

#include "engine/error.h"
#include "engine/formats/gltf_check.h"
#include "engine/formats/ply_check.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace arbor::engine::formats {

namespace {

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

/// "solid" at the start (after blanks), "facet" or "endsolid" soon after, and no NUL byte in the
/// first kilobyte: binary STL headers often start with "solid" too.
bool looks_like_stl_ascii(std::string_view b) {
    std::size_t i = 0;
    while (i < b.size() && std::isspace(static_cast<unsigned char>(b[i]))) ++i;
    if (b.substr(i, 5) != "solid") return false;
    const std::string_view head = b.substr(0, 1024);
    if (head.find('\0') != std::string_view::npos) return false;
    return head.find("facet") != std::string_view::npos || head.find("endsolid") != std::string_view::npos;
}

}  // namespace

const char* format_name(MeshFormat f) {
    switch (f) {
    case MeshFormat::obj: return "OBJ";
    case MeshFormat::ply: return "PLY";
    case MeshFormat::stl_ascii:
    case MeshFormat::stl_binary: return "STL";
    case MeshFormat::gltf: return "glTF";
    case MeshFormat::glb: return "GLB";
    }
    return "?";
}

long long stl_binary_count(std::string_view b) {
    if (b.size() < 84) return -1;
    std::uint32_t n = 0;
    for (int k = 0; k < 4; ++k) n |= std::uint32_t(static_cast<unsigned char>(b[80 + std::size_t(k)])) << (8 * k);
    return (long long)n;
}

void check_stl_binary(std::string_view b, const std::string& name) {
    const long long n = stl_binary_count(b);
    if (n < 0) throw InputError(name, 0, "binary STL of " + std::to_string(b.size()) + " bytes is shorter than its 84-byte header");
    const std::uint64_t need = 84 + 50 * std::uint64_t(n);
    if (need != b.size())
        throw InputError(name, 0, "binary STL header says " + std::to_string(n) + " triangles (" + std::to_string(need) +
                                      " bytes), the file has " + std::to_string(b.size()) + " bytes" +
                                      (need > b.size() ? " (truncated?)" : ""));
}

MeshFormat detect_mesh_format(std::string_view b, const std::string& path) {
    if (looks_like_ply(b)) return MeshFormat::ply;
    if (looks_like_glb(b)) return MeshFormat::glb;
    if (looks_like_json(b)) return MeshFormat::gltf;
    const long long n = stl_binary_count(b);
    if (n >= 0 && 84 + 50 * std::uint64_t(n) == b.size()) return MeshFormat::stl_binary;
    if (looks_like_stl_ascii(b)) return MeshFormat::stl_ascii;
    // The content says nothing clear: a file named for a format is reported as that format broken.
    const std::string ext = lower_extension(path);
    if (ext == ".stl") return MeshFormat::stl_binary;
    if (ext == ".ply") return MeshFormat::ply;
    if (ext == ".glb") return MeshFormat::glb;
    if (ext == ".gltf") return MeshFormat::gltf;
    return MeshFormat::obj;
}

}  // namespace arbor::engine::formats
