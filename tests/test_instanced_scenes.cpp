// Engine scenes of instances (engine/mesh_instances.h) against their flattened forms: a glTF file
// whose nodes place one mesh five times (nested transforms, a mirrored and non-uniformly scaled
// node), read as instances and read flattened as before; and the built-in field, small. Every
// ray farther than 1e-6 of the scene's diagonal from an edge of the triangle it hits gets the
// same answer (hit or miss, triangle number; t within 1e-6 relative, or within 1e-6 of the
// diagonal for hits nearer than the scene's size); the renderer draws both alike.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "accel/factory/make_accel.h"
#include "engine/builtin_scenes.h"
#include "engine/error.h"
#include "engine/mesh_instances.h"
#include "engine/mesh_loader.h"
#include "engine/procedural.h"
#include "engine/renderer.h"
#include "engine/smooth_normals.h"
#include "instance_scenes.h"
#include "testing.h"

using namespace arbor;

namespace {

std::string base64(const std::string& in) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < in.size(); i += 3) {
        const std::uint32_t b0 = std::uint8_t(in[i]), b1 = i + 1 < in.size() ? std::uint8_t(in[i + 1]) : 0,
                            b2 = i + 2 < in.size() ? std::uint8_t(in[i + 2]) : 0;
        const std::uint32_t v = (b0 << 16) | (b1 << 8) | b2;
        out += digits[(v >> 18) & 63];
        out += digits[(v >> 12) & 63];
        out += i + 1 < in.size() ? digits[(v >> 6) & 63] : '=';
        out += i + 2 < in.size() ? digits[v & 63] : '=';
    }
    return out;
}

/// A glTF of one icosphere (320 triangles) placed by five nodes: a turned and moved root whose
/// child (scaled by 1/2) has a child of its own given by a matrix (a turn about x and a move); a
/// mirrored, non-uniformly scaled node; and one moved only.
std::string five_placements_gltf() {
    const engine::Mesh m = engine::make_icosphere({0, 0, 0}, 1.0f, 2, 0.1f, 4);
    std::string bytes;
    for (std::size_t v = 0; v < m.vertex_count(); ++v)
        for (const float c : {m.x[v], m.y[v], m.z[v]}) bytes.append(reinterpret_cast<const char*>(&c), 4);
    const std::size_t positions = bytes.size();
    for (const std::uint32_t i : m.indices) bytes.append(reinterpret_cast<const char*>(&i), 4);
    const float c = std::cos(0.7f), s = std::sin(0.7f);
    const std::string matrix = "[1,0,0,0, 0," + std::to_string(c) + "," + std::to_string(s) + ",0, 0," +
                               std::to_string(-s) + "," + std::to_string(c) + ",0, 0.5,1.5,0.25,1]";
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 3, 4]}],
  "nodes": [
    {"mesh": 0, "translation": [3, 0, 0], "rotation": [0, 0.3826834, 0, 0.9238795], "children": [1]},
    {"mesh": 0, "translation": [0, 2.5, 0], "scale": [0.5, 0.5, 0.5], "children": [2]},
    {"mesh": 0, "matrix": )" +
           matrix + R"(},
    {"mesh": 0, "translation": [-3, 0.5, 0], "scale": [-1, 1.5, 0.75]},
    {"mesh": 0, "translation": [0, 0, -3]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "buffers": [{"byteLength": )" +
           std::to_string(bytes.size()) + R"(, "uri": "data:application/octet-stream;base64,)" + base64(bytes) + R"("}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": )" +
           std::to_string(positions) + R"(},
                  {"buffer": 0, "byteOffset": )" +
           std::to_string(positions) + R"(, "byteLength": )" + std::to_string(bytes.size() - positions) + R"(}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": )" +
           std::to_string(m.vertex_count()) + R"(, "type": "VEC3", "min": [-1.2, -1.2, -1.2], "max": [1.2, 1.2, 1.2]},
                {"bufferView": 1, "componentType": 5125, "count": )" +
           std::to_string(m.indices.size()) + R"(, "type": "SCALAR"}]})";
}

/// The answers of `a` for `rays` (closest hits).
std::vector<accel::Hit> closest(const accel::Accel& a, const std::vector<accel::Ray>& rays) {
    std::vector<accel::Hit> hits(rays.size());
    a.trace(rays, hits, {accel::Query::closest, accel::TracePath::best, {}});
    return hits;
}

/// Rays whose answers on the instanced structure and the flattened one differ, among those that
/// hit (on either) no nearer than 1e-6 of the diagonal to an edge of `flat`; `compared` and
/// `hits` count the rays compared and the hits among them.
std::size_t differences(const engine::Mesh& flat, const accel::Accel& placed, const accel::Accel& flattened,
                        const std::vector<accel::Ray>& rays, std::size_t& compared, std::size_t& hits) {
    const accel::Vec3f e = flat.bounds.extent();
    const double diagonal = std::sqrt(double(e.x) * e.x + double(e.y) * e.y + double(e.z) * e.z);
    const auto p = closest(placed, rays), f = closest(flattened, rays);
    auto near_edge = [&](const accel::Hit& h) {
        return h.is_hit() && testing::edge_distance(flat, h.prim, h.u, h.v) < 1e-6 * diagonal;
    };
    std::size_t differ = 0;
    compared = hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (near_edge(p[i]) || near_edge(f[i])) continue;
        ++compared, hits += f[i].is_hit();
        const double len = std::sqrt(double(rays[i].dir.x) * rays[i].dir.x + double(rays[i].dir.y) * rays[i].dir.y +
                                     double(rays[i].dir.z) * rays[i].dir.z);
        const bool same = p[i].is_hit() == f[i].is_hit() &&
                          (!f[i].is_hit() ||
                           (p[i].prim == f[i].prim && std::fabs(double(p[i].t) - double(f[i].t)) <=
                                                          1e-6 * std::max(std::fabs(double(f[i].t)), diagonal / len)));
        if (!same && ++differ <= 3)
            MESSAGE("ray ", i, ": flattened t ", f[i].t, " prim ", f[i].prim, "; instanced t ", p[i].t, " prim ",
                    p[i].prim);
    }
    return differ;
}

}  // namespace

TEST_CASE("glTF: nodes that place one mesh five times load as instances, with the flattened file's hits") {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "arbor-instanced-gltf";
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "five.gltf").string();
    std::ofstream(path) << five_placements_gltf();

    engine::Warnings warnings;
    engine::MeshInstances placed;
    const engine::Mesh mesh = engine::load_mesh(path, warnings, 0, nullptr, &placed);
    const engine::Mesh flat = engine::load_mesh(path, warnings);
    REQUIRE(!placed.empty());
    CHECK(placed.parts.size() == 1);
    CHECK(placed.instances.size() == 5);
    CHECK(placed.drawn == 0);
    CHECK(mesh.triangle_count() == 320);  // the mesh once
    CHECK(placed.effective_triangles() == 5 * 320);
    CHECK(flat.triangle_count() == 5 * 320);
    // One instance mirrors (det < 0); the nested one carries its parents' scale of 1/2.
    int mirrored = 0;
    for (const engine::PartInstance& i : placed.instances) mirrored += i.transform.det() < 0.0;
    CHECK(mirrored == 1);
    CHECK(std::fabs(placed.instances[2].transform.det()) == doctest::Approx(0.125));

    // flatten() gives the flattened file's corners (rounded once from double there, from float
    // products in Assimp) and its box.
    const engine::Mesh mine = engine::flatten(mesh, placed);
    REQUIRE(mine.triangle_count() == flat.triangle_count());
    double worst = 0;
    for (std::size_t t = 0; t < flat.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst,
                                 std::fabs(double(mine.view().corner(t, k)[c]) - double(flat.view().corner(t, k)[c])));
    CHECK(worst < 1e-5);
    const accel::Bounds box = engine::world_bounds(mesh, placed, true);
    for (int c = 0; c < 3; ++c) {
        CHECK(box.lo[c] == doctest::Approx(flat.bounds.lo[c]).epsilon(1e-6));
        CHECK(box.hi[c] == doctest::Approx(flat.bounds.hi[c]).epsilon(1e-6));
    }

    for (const auto kind : {accel::AccelKind::bvh_sah, accel::AccelKind::kdtree, accel::AccelKind::brute}) {
        CAPTURE(accel::to_string(kind));
        const auto inst = engine::make_instanced_accel(mesh, placed, kind, {});
        const auto ref = accel::make_accel(kind, flat.view(), {});
        CHECK(inst->stats().triangles == flat.triangle_count());
        std::size_t compared = 0, hits = 0;
        CHECK(differences(flat, *inst, *ref, testing::three_kinds(flat.bounds, 3000, 7), compared, hits) == 0);
        CHECK(compared > 8000);
        CHECK(hits > compared / 8);
    }
    std::filesystem::remove_all(dir);
}

TEST_CASE("built-in field: instances of four models, the hits of its flattened copy, rendered alike") {
    const engine::Scene placed = engine::make_builtin_scene("builtin:field:2", true);
    const engine::Scene flat = engine::make_builtin_scene("builtin:field:2");  // flattened: fits easily
    REQUIRE(placed.placed.instances.size() == 4);
    CHECK(placed.placed.parts.size() == 4);
    CHECK(placed.placed.drawn == 2);  // the ground
    CHECK(flat.placed.empty());
    CHECK(flat.mesh.triangle_count() == placed.placed.effective_triangles());
    CHECK(placed.mesh.triangle_count() == 2 + 81920 + 327680 + 160000 + 131072);
    // The default field: 10,000 instances, over a billion placed triangles, numbered in 32 bits.
    {
        engine::Scene s = engine::make_field_scene(100);
        CHECK(s.placed.instances.size() == 10000);
        CHECK(s.placed.effective_triangles() > 1000000000ull);
        CHECK(s.placed.effective_triangles() < 0xFFFFFFFFull);
        CHECK(s.mesh.triangle_count() == placed.mesh.triangle_count());
    }
    CHECK_THROWS_AS(engine::make_builtin_scene("builtin:field:0"), engine::InputError);
    CHECK_THROWS_AS(engine::make_builtin_scene("builtin:field:121"), engine::InputError);

    const auto inst = engine::make_instanced_accel(placed.mesh, placed.placed, accel::AccelKind::bvh_sah, {});
    const auto ref = accel::make_accel(accel::AccelKind::bvh_sah, flat.mesh.view(), {});
    std::size_t compared = 0, hits = 0;
    CHECK(differences(flat.mesh, *inst, *ref, testing::three_kinds(flat.mesh.bounds, 3000, 11), compared, hits) == 0);
    CHECK(compared > 8000);
    CHECK(hits > compared / 5);

    // The renderer (direct light, shadow rays) draws the instances as it draws the flattened copy:
    // pixels differ only where a ray meets an edge (rounding), a handful.
    engine::RenderSettings set;
    set.width = 96, set.height = 64, set.spp = 1, set.jitter = false;
    const engine::Image a = engine::render(placed, *inst, set), b = engine::render(flat, *ref, set);
    std::size_t differ = 0, lit = 0;
    for (int y = 0; y < set.height; ++y)
        for (int x = 0; x < set.width; ++x) {
            lit += a.at(0, x, y) > 0.0f;
            for (int c = 0; c < 3; ++c)
                differ += std::fabs(a.at(c, x, y) - b.at(c, x, y)) > 1e-3f * (1.0f + b.at(c, x, y));
        }
    CHECK(lit > std::size_t(set.width * set.height / 2));
    CHECK(differ <= std::size_t(set.width * set.height / 100));

    // With vertex normals (shading normals carried by the inverse transpose, Hanika's point
    // carried by the transform) against flatten(), which carries the normals the same way.
    engine::Scene smooth = engine::make_builtin_scene("builtin:field:2", true);
    REQUIRE(engine::compute_smooth_normals(smooth.mesh) > 0);
    engine::Scene smooth_flat = smooth;
    smooth_flat.mesh = engine::flatten(smooth.mesh, smooth.placed);
    smooth_flat.placed = {};
    REQUIRE(smooth_flat.mesh.has_normals());
    const auto sref = accel::make_accel(accel::AccelKind::bvh_sah, smooth_flat.mesh.view(), {});
    const engine::Image sa = engine::render(smooth, *inst, set), sb = engine::render(smooth_flat, *sref, set);
    std::size_t smooth_differ = 0, smooth_changed = 0;
    for (int y = 0; y < set.height; ++y)
        for (int x = 0; x < set.width; ++x)
            for (int c = 0; c < 3; ++c) {
                smooth_differ += std::fabs(sa.at(c, x, y) - sb.at(c, x, y)) > 1e-3f * (1.0f + sb.at(c, x, y));
                smooth_changed += std::fabs(sa.at(c, x, y) - a.at(c, x, y)) > 1e-3f * (1.0f + a.at(c, x, y));
            }
    CHECK(smooth_changed > std::size_t(set.width * set.height / 20));  // the normals are read
    CHECK(smooth_differ <= std::size_t(set.width * set.height / 100));
}
