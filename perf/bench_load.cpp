// bench_load: loading speed per format, in seconds per million triangles. The largest shared model
// (the Stanford bunny, 69,451 triangles) is replicated side by side to about --triangles triangles
// and written as OBJ, binary little-endian PLY and GLB (perf/mesh_files.h); each file is then
// loaded by engine::load_mesh, and the OBJ also by Assimp's own OBJ reader (Assimp::Importer, no
// post-processing: the scene Assimp builds, not converted to arbor's mesh), --repeat rounds, the
// order of the readers rotated every round so that drift on a shared machine spreads over all of
// them. With --arbor, each round also times a fresh `arbor info FILE` process (the wall clock a
// user feels: reading the file from the page cache, loading, counting, exiting).
//
//   bench_load [--model PATH] [--triangles N] [--repeat K] [--dir DIR] [--arbor PATH] [--keep]
#include "accel/util/timer.h"
#include "engine/log.h"
#include "engine/mesh_loader.h"
#include "engine/obj_loader.h"
#include "perf/mesh_files.h"

#include <CLI/CLI.hpp>
#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include <algorithm>
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

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"bench_load: seconds per million triangles for each mesh format"};
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
                                   {"arbor binary PLY (checks + Assimp)", ply, Reader::arbor_loader},
                                   {"arbor GLB (checks + Assimp)", glb, Reader::arbor_loader},
                                   {"Assimp's OBJ reader alone", obj, Reader::assimp}};
    if (!arbor_binary.empty())
        for (const auto& [name, file] : {std::pair{"arbor info, OBJ (fresh process)", obj}, std::pair{"arbor info, PLY (fresh process)", ply},
                                         std::pair{"arbor info, GLB (fresh process)", glb}})
            readers.push_back({name, file, Reader::process});
    std::map<std::string, std::vector<double>> seconds;
    for (int round = 0; round < repeat; ++round)
        for (std::size_t k = 0; k < readers.size(); ++k) {
            const Reader& r = readers[(k + std::size_t(round)) % readers.size()];
            const accel::Timer t;
            std::size_t triangles = 0;
            if (r.how == Reader::arbor_loader) {
                engine::Warnings lw;
                triangles = engine::load_mesh(r.file, lw).triangle_count();
            } else if (r.how == Reader::assimp) {
                Assimp::Importer importer;
                const aiScene* s = importer.ReadFile(r.file, 0);
                if (!s) throw std::runtime_error(std::string("Assimp: ") + importer.GetErrorString());
                for (unsigned m = 0; m < s->mNumMeshes; ++m) triangles += s->mMeshes[m]->mNumFaces;
            } else {
                const std::string cmd = "'" + arbor_binary + "' info '" + r.file + "' >/dev/null";
                if (std::system(cmd.c_str()) != 0) throw std::runtime_error("failed: " + cmd);
                triangles = mesh.triangle_count();
            }
            seconds[r.name].push_back(t.seconds());
            if (triangles != mesh.triangle_count())
                std::fprintf(stderr, "%s read %zu triangles, expected %zu\n", r.name.c_str(), triangles, mesh.triangle_count());
        }
    std::printf("\n| reader | file | s per M triangles (median of %d) | min - max | whole file, median s |\n|---|---|---:|---:|---:|\n", repeat);
    for (const Reader& r : readers) {
        const auto& v = seconds[r.name];
        const double med = median(v);
        std::printf("| %s | %s | %.3f | %.3f - %.3f | %.2f |\n", r.name.c_str(), std::filesystem::path(r.file).extension().c_str(),
                    med / tri_m, *std::min_element(v.begin(), v.end()) / tri_m, *std::max_element(v.begin(), v.end()) / tri_m, med);
    }
    if (!keep) std::filesystem::remove_all(dir);
    return 0;
}
