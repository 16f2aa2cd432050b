/// `arbor info MODEL [--json] [--accel NAME] [--leaf-size N] [--sah-bins N]`: counts, bounds, warnings; with --accel also the
/// build statistics of that structure.
#include "apps/arbor/commands.h"
#include "apps/arbor/common.h"
#include "accel/dispatch/kernel_set.h"
#include "accel/factory/make_accel.h"
#include "engine/log.h"
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
std::size_t count_degenerate(const engine::Mesh& m) {
    std::size_t n = 0;
    const auto v = m.view();
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        const auto a = v.corner(t, 0), b = v.corner(t, 1), c = v.corner(t, 2);
        const double e1[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
        const double e2[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
        const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                     cz = e1[0] * e2[1] - e1[1] * e2[0];
        n += (cx == 0.0 && cy == 0.0 && cz == 0.0);
    }
    return n;
}

int run_info(const InfoOptions& o) {
    engine::Warnings warnings;
    engine::MeshFormat format{};
    const engine::Mesh mesh = engine::load_mesh(o.model, warnings, o.build.max_memory, &format);
    nlohmann::json j;
    j["file"] = o.model;
    j["format"] = engine::formats::format_name(format);
    j["triangles"] = mesh.triangle_count();
    j["vertices"] = mesh.vertex_count();
    j["degenerate_triangles"] = count_degenerate(mesh);
    j["materials"] = mesh.materials.size();
    j["normals"] = mesh.normals.size();
    j["texture_coordinates"] = mesh.uvs.size();
    j["vertex_colors"] = !mesh.colors.empty();
    j["textures"] = mesh.textures.size();
    j["bounds"] = {{"min", {mesh.bounds.lo.x, mesh.bounds.lo.y, mesh.bounds.lo.z}},
                   {"max", {mesh.bounds.hi.x, mesh.bounds.hi.y, mesh.bounds.hi.z}}};
    j["warnings"] = warnings.lines;
    // The SIMD kernel set in use, those the build holds, and what the one in use lacks (README,
    // "One build for any x86-64").
    j["kernel_set"] = std::string(accel::kernel_set());
    j["kernel_sets_built"] = nlohmann::json::array();
    for (const std::string_view s : accel::kernel_sets_built()) j["kernel_sets_built"].push_back(std::string(s));
    j["kernel_set_skipped"] = accel::kernel_set_skipped();
    if (!o.accel.empty()) {
        accel::AccelPick pick = resolve_accel(o.accel, mesh.view(), o.build);
        const auto kind = pick.kind;
        const auto accel = pick.built ? std::move(pick.built) : accel::make_accel(kind, mesh.view(), o.build);
        j["accel"] = accel::to_string(kind);
        if (!pick.reason.empty()) j["auto_reason"] = pick.reason;
        j["build_ms"] = accel->stats().build_ms;
        j["leaf_size"] = o.build.bvh.max_leaf_size;
        put_stats(j, accel->stats());
    }
    if (o.json) {
        std::cout << j.dump() << '\n';
        return 0;
    }
    engine::print_warnings(warnings);
    std::printf("%s (%s): %zu triangles (%zu degenerate), %zu vertices, %zu materials, %zu normals, %zu texture coordinates, "
                "%zu textures%s\n",
                o.model.c_str(), engine::formats::format_name(format), mesh.triangle_count(),
                std::size_t(j["degenerate_triangles"]), mesh.vertex_count(), mesh.materials.size(), mesh.normals.size(),
                mesh.uvs.size(), mesh.textures.size(), mesh.colors.empty() ? "" : ", vertex colours");
    std::printf("bounds: [%g %g %g] .. [%g %g %g]\n", mesh.bounds.lo.x, mesh.bounds.lo.y, mesh.bounds.lo.z,
                mesh.bounds.hi.x, mesh.bounds.hi.y, mesh.bounds.hi.z);
    const std::string skipped = accel::kernel_set_skipped();
    std::printf("SIMD kernels: %s%s%s\n", std::string(accel::kernel_set()).c_str(), skipped.empty() ? "" : " (",
                skipped.empty() ? "" : (skipped + ")").c_str());
    if (j.contains("accel"))
        std::printf("%s: built in %.2f ms, %zu nodes, %zu leaves, max depth %u, SAH cost %.2f, %.1f bytes/triangle\n",
                    std::string(j["accel"]).c_str(), double(j["build_ms"]), std::size_t(j["nodes"]),
                    std::size_t(j["leaves"]), unsigned(j["max_depth"]), double(j["sah_cost"]),
                    double(j["bytes_per_triangle"]));
    return 0;
}

}  // namespace

Run add_info(CLI::App& cmd) {
    auto o = std::make_shared<InfoOptions>();
    cmd.add_option("MODEL", o->model, "mesh file: OBJ, PLY, STL or glTF 2.0 (.gltf, .glb), told by its content")->required();
    add_accel_option(cmd, o->accel);
    add_build_options(cmd, o->build);
    cmd.add_flag("--json", o->json, "one JSON object on standard output");
    return [o] { return run_info(*o); };
}

}  // namespace arbor::app
