// `arbor-bench load`: loading speed per format, in seconds per million triangles. The largest shared model
// (the Stanford bunny, 69,451 triangles) is replicated side by side to about --triangles triangles
// and written as OBJ, binary little-endian PLY and GLB (perf/mesh_files.h); each file is then
// loaded by engine::load_mesh, and the OBJ also by Assimp's own OBJ reader (Assimp::Importer, no
// post-processing: the scene Assimp builds, not converted to arbor's mesh), --repeat rounds, the
// order of the readers rotated every round so that drift on a shared machine spreads over all of
// them. With --arbor, each round also times a fresh `arbor info FILE` process (the wall clock a
// user feels: reading the file from the page cache, loading, counting, exiting).
// The accuracy figure beside each speed: every reader's triangle count and the largest difference
// between its triangles' corner positions and the replicated mesh's, triangle by triangle (outside
// the timed region; the fresh processes report only their triangle count, parsed from `arbor info`).
//
//   arbor-bench load [--model PATH] [--triangles N] [--repeat K] [--dir DIR] [--arbor PATH] [--keep]
#include "perf/commands.h"
#include "accel/util/timer.h"
#include "engine/log.h"
#include "engine/mesh_loader.h"
#include "engine/obj_loader.h"
#include "perf/mesh_files.h"

#include <CLI/CLI.hpp>
#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <unistd.h>

#ifndef ARBOR_SHARED_SCENES
#define ARBOR_SHARED_SCENES "../shared/scenes"
#endif

using namespace arbor;

namespace {

struct Reader {
    std::string name, file;
    enum { arbor_loader, assimp, process } how;
};

/// Largest |difference| of a corner coordinate between triangle t of `got` and of `want`, over all
/// triangles; infinity when the triangle counts differ.
double max_corner_error(const engine::Mesh& got, const engine::Mesh& want) {
    if (got.triangle_count() != want.triangle_count()) return HUGE_VAL;
    double e = 0;
    for (std::size_t k = 0; k < want.indices.size(); ++k) {
        const std::uint32_t a = got.indices[k], b = want.indices[k];
        e = std::max({e, std::fabs(double(got.x[a]) - want.x[b]), std::fabs(double(got.y[a]) - want.y[b]),
                      std::fabs(double(got.z[a]) - want.z[b])});
    }
    return e;
}

/// The same for Assimp's scene: its meshes' faces in order (non-triangles count as a mismatch).
double max_corner_error(const aiScene& s, const engine::Mesh& want, std::size_t& triangles) {
    triangles = 0;
    for (unsigned m = 0; m < s.mNumMeshes; ++m) triangles += s.mMeshes[m]->mNumFaces;
    if (triangles != want.triangle_count()) return HUGE_VAL;
    double e = 0;
    std::size_t k = 0;
    for (unsigned m = 0; m < s.mNumMeshes; ++m)
        for (unsigned f = 0; f < s.mMeshes[m]->mNumFaces; ++f) {
            const aiFace& face = s.mMeshes[m]->mFaces[f];
            if (face.mNumIndices != 3) return HUGE_VAL;
            for (unsigned c = 0; c < 3; ++c, ++k) {
                const aiVector3D& p = s.mMeshes[m]->mVertices[face.mIndices[c]];
                const std::uint32_t b = want.indices[k];
                e = std::max({e, std::fabs(double(p.x) - want.x[b]), std::fabs(double(p.y) - want.y[b]), std::fabs(double(p.z) - want.z[b])});
            }
        }
    return e;
}

/// Triangle count from the first line of `arbor info FILE` ("FILE (FORMAT): N triangles ...").
std::size_t info_triangles(const std::string& cmd) {
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) throw std::runtime_error("cannot run: " + cmd);
    char line[4096] = {};
    const bool got = std::fgets(line, sizeof line, p) != nullptr;
    char rest[4096];
    while (std::fgets(rest, sizeof rest, p)) {
    }
    if (::pclose(p) != 0 || !got) throw std::runtime_error("failed: " + cmd);
    const char* at = std::strstr(line, "): ");
    return at ? std::strtoull(at + 3, nullptr, 10) : 0;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

static int load_main(int argc, char** argv) {
    CLI::App app{"arbor-bench load: seconds per million triangles for each mesh format"};
    std::string model = std::string(ARBOR_SHARED_SCENES) + "/models/stanford-bunny.obj";
    std::size_t target = 5000000;
    int repeat = 5;
    std::string dir = (std::filesystem::temp_directory_path() / ("arbor-bench-load-" + std::to_string(::getpid()))).string();
    std::string arbor_binary;
    bool keep = false;
    app.add_option("--model", model, "OBJ model to replicate")->capture_default_str();
    app.add_option("--triangles", target, "about this many triangles")->check(CLI::Range(std::size_t(1), std::size_t(1) << 30))->capture_default_str();
    app.add_option("--repeat", repeat, "rounds (readers interleaved, order rotated)")->check(CLI::Range(1, 100))->capture_default_str();
    app.add_option("--dir", dir, "where the files are written");
    app.add_option("--arbor", arbor_binary, "also time fresh `arbor info FILE` processes with this binary");
    app.add_flag("--keep", keep, "keep the files");
    CLI11_PARSE(app, argc, argv);

    engine::Warnings w;
    const engine::Mesh base = engine::load_obj(model, w);
    const int copies = int((target + base.triangle_count() - 1) / base.triangle_count());
    const engine::Mesh mesh = perf::replicate(base, copies);
    std::filesystem::create_directories(dir);
    const accel::Timer write_timer;
    auto write = [&](const std::string& name, const std::string& bytes) {
        const std::string path = dir + "/" + name;
        std::ofstream(path, std::ios::binary) << bytes;
        return path;
    };
    const std::string obj = write("model.obj", perf::obj_text(mesh));
    const std::string ply = write("model.ply", perf::ply_bytes(mesh, perf::PlyEncoding::binary_little_endian));
    const std::string glb = write("model.glb", perf::gltf_bytes(mesh, {}));
    const double tri_m = double(mesh.triangle_count()) * 1e-6;
    std::printf("%s x %d = %zu triangles, %zu vertices; files written in %.1f s to %s\n", model.c_str(), copies,
                mesh.triangle_count(), mesh.vertex_count(), write_timer.seconds(), dir.c_str());
    for (const auto& f : {obj, ply, glb})
        std::printf("  %s: %.1f MB\n", f.c_str(), double(std::filesystem::file_size(f)) * 1e-6);

    std::vector<Reader> readers = {{"arbor OBJ (tinyobjloader + checks)", obj, Reader::arbor_loader},
                                   {"arbor binary PLY", ply, Reader::arbor_loader},
                                   {"arbor GLB (checks + Assimp)", glb, Reader::arbor_loader},
                                   {"Assimp's OBJ reader alone", obj, Reader::assimp}};
    if (!arbor_binary.empty())
        for (const auto& [name, file] : {std::pair{"arbor info, OBJ (fresh process)", obj}, std::pair{"arbor info, PLY (fresh process)", ply},
                                         std::pair{"arbor info, GLB (fresh process)", glb}})
            readers.push_back({name, file, Reader::process});
    std::map<std::string, std::vector<double>> seconds;
    std::map<std::string, double> error;
    std::map<std::string, std::size_t> counted;
    for (int round = 0; round < repeat; ++round)
        for (std::size_t k = 0; k < readers.size(); ++k) {
            const Reader& r = readers[(k + std::size_t(round)) % readers.size()];
            accel::Timer t;
            double seconds_taken = 0, err = HUGE_VAL;
            std::size_t triangles = 0;
            if (r.how == Reader::arbor_loader) {
                engine::Warnings lw;
                const engine::Mesh got = engine::load_mesh(r.file, lw);
                seconds_taken = t.seconds();
                triangles = got.triangle_count();
                err = max_corner_error(got, mesh);
            } else if (r.how == Reader::assimp) {
                Assimp::Importer importer;
                const aiScene* s = importer.ReadFile(r.file, 0);
                seconds_taken = t.seconds();
                if (!s) throw std::runtime_error(std::string("Assimp: ") + importer.GetErrorString());
                err = max_corner_error(*s, mesh, triangles);
            } else {
                triangles = info_triangles("'" + arbor_binary + "' info '" + r.file + "'");
                seconds_taken = t.seconds();
            }
            seconds[r.name].push_back(seconds_taken);
            error[r.name] = std::max(error.count(r.name) ? error[r.name] : 0.0, err);
            counted[r.name] = triangles;
            if (triangles != mesh.triangle_count())
                std::fprintf(stderr, "%s read %zu triangles, expected %zu\n", r.name.c_str(), triangles, mesh.triangle_count());
        }
    std::printf("\n| reader | file | s per M triangles (median of %d) | min - max | whole file, median s | triangles read | max corner error |\n"
                "|---|---|---:|---:|---:|---:|---:|\n", repeat);
    for (const Reader& r : readers) {
        const auto& v = seconds[r.name];
        const double med = median(v);
        char err[32] = "not read back";
        if (r.how != Reader::process) std::snprintf(err, sizeof err, "%.3g", error[r.name]);
        std::printf("| %s | %s | %.3f | %.3f - %.3f | %.2f | %zu | %s |\n", r.name.c_str(), std::filesystem::path(r.file).extension().c_str(),
                    med / tri_m, *std::min_element(v.begin(), v.end()) / tri_m, *std::max_element(v.begin(), v.end()) / tri_m, med,
                    counted[r.name], err);
    }
    if (!keep) std::filesystem::remove_all(dir);
    return 0;
}

int arbor::perf::load_command(int argc, char** argv) { return load_main(argc, argv); }
