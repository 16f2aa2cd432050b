/// `arbor info MODEL [--json] [--accel NAME] [--leaf-size N] [--sah-bins N]`: counts, bounds, warnings; with --accel also the
/// build statistics of that structure.
#include "apps/arbor/commands.h"
#include "apps/arbor/common.h"
#include "accel/dispatch/kernel_set.h"
#include "accel/factory/make_accel.h"
#include "engine/builtin_scenes.h"
#include "engine/log.h"
#include "engine/memory_budget.h"
#include "engine/mesh_instances.h"
#include "engine/mesh_loader.h"

#include <cstdio>
#include <iostream>
#include <memory>

namespace arbor::app {

namespace {

struct InfoOptions {
    std::string model;
    std::string accel;
    accel::BuildConfig build;
    bool json = false;
};

/// Triangles whose exact cross product is zero (zero area or collinear); they are kept and numbered
/// but can never be hit.
std::size_t count_degenerate(const engine::Mesh& m, std::size_t first, std::size_t end) {
    std::size_t n = 0;
    const auto v = m.view();
    for (std::size_t t = first; t < end; ++t) {
        const auto a = v.corner(t, 0), b = v.corner(t, 1), c = v.corner(t, 2);
        const double e1[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
        const double e2[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
        const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                     cz = e1[0] * e2[1] - e1[1] * e2[0];
        n += (cx == 0.0 && cy == 0.0 && cz == 0.0);
    }
    return n;
}

/// Degenerate triangles placed: those drawn as they are, and each instance's part's (counted in
/// the mesh's own coordinates) as often as it is placed.
std::uint64_t placed_degenerate(const engine::Mesh& m, const engine::MeshInstances& placed) {
    if (placed.empty()) return count_degenerate(m, 0, m.triangle_count());
    std::uint64_t n = count_degenerate(m, 0, placed.drawn);
    std::vector<std::uint64_t> per_part(placed.parts.size());
    for (std::size_t p = 0; p < placed.parts.size(); ++p)
        per_part[p] = count_degenerate(m, placed.parts[p].first, std::size_t(placed.parts[p].first) + placed.parts[p].count);
    for (const engine::PartInstance& i : placed.instances) n += per_part[i.part];
    return n;
}

int run_info(const InfoOptions& o) {
    engine::Warnings warnings;
    engine::MeshFormat format{};
    engine::Mesh mesh;
    engine::MeshInstances placed;
    const bool builtin = engine::is_builtin_scene(o.model);
    if (builtin) {
        engine::Scene scene = engine::make_builtin_scene(o.model, true);
        mesh = std::move(scene.mesh);
        placed = std::move(scene.placed);
    } else {
        mesh = engine::load_mesh(o.model, warnings, o.build.max_memory, &format, &placed);
    }
    const std::uint64_t effective = placed.empty() ? mesh.triangle_count() : placed.effective_triangles();
    // A built-in field of a billion triangles gets the parts' boxes carried over (cheap); a
    // file the exact box of its placed vertices.
    const engine::Bounds bounds = engine::world_bounds(mesh, placed, !builtin);
    nlohmann::json j;
    j["file"] = o.model;
    j["format"] = builtin ? "built-in" : engine::formats::format_name(format);
    j["triangles"] = effective;
    // Vertices, normals and texture coordinates as the flattened file holds them (each placement
    // its own), like the triangles.
    using engine::MeshPart;
    const std::uint64_t vertices = placed.effective(mesh.vertex_count(), &MeshPart::vertices);
    const std::uint64_t normals = placed.effective(mesh.normals.size(), &MeshPart::normals);
    const std::uint64_t uvs = placed.effective(mesh.uvs.size(), &MeshPart::uvs);
    j["vertices"] = vertices;
    j["degenerate_triangles"] = placed_degenerate(mesh, placed);
    j["instances"] = placed.instances.size();
    j["unique_triangles"] = mesh.triangle_count();
    j["unique_vertices"] = mesh.vertex_count();
    j["effective_triangles"] = effective;
    j["materials"] = mesh.materials.size();
    j["normals"] = normals;
    j["texture_coordinates"] = uvs;
    j["vertex_colors"] = !mesh.colors.empty();
    j["textures"] = mesh.textures.size();
    j["bounds"] = {{"min", {bounds.lo.x, bounds.lo.y, bounds.lo.z}}, {"max", {bounds.hi.x, bounds.hi.y, bounds.hi.z}}};
    j["warnings"] = warnings.lines;
    // The SIMD kernel set in use, those the build holds, and what the one in use lacks (README,
    // "One build for any x86-64").
    j["kernel_set"] = std::string(accel::kernel_set());
    j["kernel_sets_built"] = nlohmann::json::array();
    for (const std::string_view s : accel::kernel_sets_built()) j["kernel_sets_built"].push_back(std::string(s));
    j["kernel_set_skipped"] = accel::kernel_set_skipped();
    if (!o.accel.empty()) {
        accel::AccelPick pick;
        if (placed.empty()) {
            pick = resolve_accel(o.accel, mesh.view(), o.build);
        } else {
            const auto named = accel::parse_accel_kind(o.accel);
            if (!named) throw OptionError("--accel: unknown structure '" + o.accel + "'");
            pick.kind = *named == accel::AccelKind::automatic ? accel::AccelKind::bvh_sah : *named;
            if (*named == accel::AccelKind::automatic) pick.reason = "the model has instances: bvh-sah for each placed mesh";
        }
        const auto kind = pick.kind;
        const auto accel = pick.built        ? std::move(pick.built)
                           : placed.empty() ? accel::make_accel(kind, mesh.view(), o.build)
                                            : engine::make_instanced_accel(mesh, placed, kind, o.build);
        j["accel"] = accel::to_string(kind);
        if (!pick.reason.empty()) j["auto_reason"] = pick.reason;
        j["build_ms"] = accel->stats().build_ms;
        j["leaf_size"] = o.build.bvh.max_leaf_size;
        put_stats(j, accel->stats());
        // What the scene holds in memory: the structure, the mesh (each part once) and the
        // transforms, per triangle held and per triangle placed.
        const double held = double(accel->stats().memory_bytes + mesh.bytes() +
                                   placed.instances.size() * sizeof(engine::PartInstance));
        j["scene_bytes"] = std::uint64_t(held);
        j["bytes_per_unique_triangle"] = mesh.triangle_count() ? held / double(mesh.triangle_count()) : 0.0;
        j["bytes_per_effective_triangle"] = effective ? held / double(effective) : 0.0;
    }
    if (o.json) {
        std::cout << j.dump() << '\n';
        return 0;
    }
    engine::print_warnings(warnings);
    std::printf(
        "%s (%s): %llu triangles (%llu degenerate), %llu vertices, %zu materials, %llu normals, %llu texture "
        "coordinates, %zu textures%s\n",
        o.model.c_str(), std::string(j["format"]).c_str(), (unsigned long long)effective,
        (unsigned long long)std::uint64_t(j["degenerate_triangles"]), (unsigned long long)vertices,
        mesh.materials.size(), (unsigned long long)normals, (unsigned long long)uvs, mesh.textures.size(),
        mesh.colors.empty() ? "" : ", vertex colours");
    if (!placed.empty())
        std::printf(
            "instances: %zu placing %llu effective triangles from %zu unique triangles, %zu vertices (each mesh "
            "held once)\n",
            placed.instances.size(), (unsigned long long)effective, mesh.triangle_count(), mesh.vertex_count());
    std::printf("bounds: [%g %g %g] .. [%g %g %g]\n", bounds.lo.x, bounds.lo.y, bounds.lo.z, bounds.hi.x, bounds.hi.y,
                bounds.hi.z);
    const std::string skipped = accel::kernel_set_skipped();
    std::printf("SIMD kernels: %s%s%s\n", std::string(accel::kernel_set()).c_str(), skipped.empty() ? "" : " (",
                skipped.empty() ? "" : (skipped + ")").c_str());
    if (j.contains("accel") && placed.empty())
        std::printf("%s: built in %.2f ms, %zu nodes, %zu leaves, max depth %u, SAH cost %.2f, %.1f bytes/triangle\n",
                    std::string(j["accel"]).c_str(), double(j["build_ms"]), std::size_t(j["nodes"]),
                    std::size_t(j["leaves"]), unsigned(j["max_depth"]), double(j["sah_cost"]),
                    double(j["bytes_per_triangle"]));
    else if (j.contains("accel"))  // depth and SAH cost belong to each mesh's structure: not summed
        std::printf(
            "%s for each of %zu meshes under a top BVH over %zu instances: built in %.2f ms, %zu nodes, %zu "
            "leaves\n",
            std::string(j["accel"]).c_str(), placed.parts.size() + (placed.drawn > 0), placed.instances.size(),
            double(j["build_ms"]), std::size_t(j["nodes"]), std::size_t(j["leaves"]));
    if (j.contains("scene_bytes"))
        std::printf("memory: %s with the mesh and transforms, %.1f bytes per unique triangle, %.3g bytes per effective triangle\n",
                    engine::format_bytes(std::uint64_t(j["scene_bytes"])).c_str(), double(j["bytes_per_unique_triangle"]),
                    double(j["bytes_per_effective_triangle"]));
    return 0;
}

}  // namespace

Run add_info(CLI::App& cmd) {
    auto o = std::make_shared<InfoOptions>();
    cmd.add_option("MODEL", o->model,
                   "mesh file: OBJ, PLY, STL or glTF 2.0 (.gltf, .glb), told by its content; or " + engine::builtin_scene_names())
        ->required();
    add_accel_option(cmd, o->accel);
    add_build_options(cmd, o->build);
    cmd.add_flag("--json", o->json, "one JSON object on standard output");
    return [o] { return run_info(*o); };
}

}  // namespace arbor::app
