#include "engine/mesh_loader.h"

#include "engine/error.h"
#include "engine/file_io.h"
#include "engine/formats/assimp_import.h"
#include "engine/formats/gltf_check.h"
#include "engine/formats/ply_check.h"
#include "engine/formats/ply_read.h"
#include "engine/memory_budget.h"
#include "engine/mesh_validate.h"
#include "engine/obj_loader.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace arbor::engine {

using namespace formats;

std::uint64_t mesh_load_bytes(MeshFormat format, std::uint64_t file_bytes) {
    return format == MeshFormat::obj ? obj_load_bytes(file_bytes) : 8 * file_bytes;
}

Mesh load_mesh_bytes(std::string_view bytes, const std::string& name, const std::string& base_dir, Warnings& warnings,
                     bool read_other_files, MeshFormat* format_out, MeshInstances* instances) {
    if (instances) *instances = {};
    const MeshFormat format = detect_mesh_format(bytes, name);
    if (format_out) *format_out = format;
    if (format == MeshFormat::obj) {
        // An OFF file (first line OFF, COFF, NOFF, STOFF, 4OFF, ...) would read as OBJ text without faces.
        const std::string_view first = bytes.substr(0, std::min(bytes.find_first_of(" \t\r\n"), bytes.size()));
        if (first.size() >= 3 && first.size() <= 8 && first.substr(first.size() - 3) == "OFF")
            throw InputError(
                name, 1,
                "an OFF file ('" + std::string(first) + "'), a format arbor does not read (OBJ, PLY, STL, glTF)");
        Mesh m = load_obj_text(std::string(bytes), name, read_other_files ? base_dir : "/nonexistent-arbor-input/", warnings);
        validate_mesh(m, name);
        return m;
    }
    GltfCounts gltf;
    switch (format) {
    case MeshFormat::ply: {
        const PlyHeader header = parse_ply_header(bytes, name);
        for (const std::string& w : header.warnings) warnings.add(w);
        check_ply_body(header, bytes, name);
        if (std::none_of(header.elements.begin(), header.elements.end(),
                         [](const PlyElement& e) { return e.name == "vertex" && e.count > 0; }))
            throw InputError(name, 0, "no triangles (the PLY file has no vertices)");
        PlyMesh ply = read_ply(header, bytes, name, warnings);
        // Faces of 1 or 2 vertices, or vertices and nothing else: say so. Strips that are all joints
        // are no points or lines.
        const bool has_lists = std::any_of(header.elements.begin(), header.elements.end(), [](const PlyElement& e) {
            return (e.name == "face" || e.name == "tristrips") && e.count > 0;
        });
        const bool only_points = ply.mesh.triangle_count() == 0 && (ply.point_line_faces > 0 || !has_lists);
        validate_mesh(ply.mesh, name, only_points ? ": the file holds only points/lines" : "");
        return std::move(ply.mesh);
    }
    case MeshFormat::stl_binary: check_stl_binary(bytes, name); break;
    case MeshFormat::gltf:
    case MeshFormat::glb: gltf = check_gltf(bytes, name); break;
    default: break;
    }
    ImportCounts counts;
    // Assimp reads other files relative to the folder; "" would mean the current one.
    const std::string dir = base_dir.empty() ? "./" : base_dir;
    Mesh m = import_with_assimp(bytes, format, name, read_other_files ? dir : "", warnings, counts, instances);
    if ((format == MeshFormat::gltf || format == MeshFormat::glb) && counts.polygons != gltf.triangles)
        throw InputError(name, 0, "glTF: the accessors define " + std::to_string(gltf.triangles) + " triangles, Assimp read " +
                                      std::to_string(counts.polygons) +
                                      " (it drops those whose indices point past their primitive's vertices)");
    const bool only_points = counts.polygons == 0 && (counts.point_line_faces > 0 || counts.vertices > 0);
    if (!only_points && gltf.point_line_prims > 0)
        warnings.add(name + ": glTF: " + std::to_string(gltf.point_line_prims) + " primitive" +
                     (gltf.point_line_prims > 1 ? "s" : "") +
                     " of points or lines not read (no surfaces), the first: " + gltf.first_point_line);
    validate_mesh(m, name, only_points ? ": the file holds only points/lines" : "");
    if (instances && !instances->empty()) instances->index(m, name);
    return m;
}

Mesh load_mesh(const std::string& path, Warnings& warnings, std::uint64_t max_bytes, MeshFormat* format_out,
               MeshInstances* instances) {
    std::error_code ec;
    const auto size = std::filesystem::is_regular_file(path, ec) ? std::filesystem::file_size(path, ec) : 0;
    const std::uint64_t budget = memory_budget(max_bytes);
    if (!ec && size > 0) {
        // The format from the first bytes alone (binary STL needs the size: it is read from the
        // file), to pick the estimate before the whole file is read.
        std::string head(std::min<std::uint64_t>(size, 4096), '\0');
        if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
            head.resize(std::fread(head.data(), 1, head.size(), f));
            std::fclose(f);
        }
        MeshFormat guess = detect_mesh_format(head, path);
        if (guess == MeshFormat::obj && size > head.size() && stl_binary_count(head) >= 0 &&
            84 + 50 * std::uint64_t(stl_binary_count(head)) == size)
            guess = MeshFormat::stl_binary;
        const std::uint64_t need = mesh_load_bytes(guess, size);
        if (need > budget)
            throw InputError(path, 0, "loading " + format_bytes(size) + " of " + format_name(guess) + " needs about " +
                                          format_bytes(need) + ", more than the " + format_bytes(budget) +
                                          (max_bytes ? " of --max-memory" : " of memory"));
    }
    const std::string bytes = read_file(path);
    const auto slash = path.find_last_of('/');
    const std::string base_dir = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
    return load_mesh_bytes(bytes, path, base_dir, warnings, true, format_out, instances);
}

}  // namespace arbor::engine
