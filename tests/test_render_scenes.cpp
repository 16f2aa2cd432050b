// Scenes for the renderer: MTL materials read from OBJ files (Kd, Ks as a mirror with illum 3..7,
// Ke as an area light), out-of-range material values clamped, lights chosen by scene_from_mesh,
// the automatic camera framing, and the built-in scenes (cornell without ../shared falls back
// to a procedural model).
#include "engine/builtin_scenes.h"
#include "engine/error.h"
#include "engine/obj_loader.h"
#include "engine/plan.h"
#include "engine/sampling.h"
#include "render_scenes.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace arbor;
using engine::Vec3f;

namespace {

/// A folder under the temporary directory, removed at the end of the scope.
struct TempDir {
    std::filesystem::path path;
    explicit TempDir(const std::string& name)
        : path(std::filesystem::temp_directory_path() / (name + "-" + std::to_string(::getpid()))) {
        std::filesystem::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    void write(const std::string& file, const std::string& text) const { std::ofstream(path / file) << text; }
};

/// Sets an environment variable for the scope, restoring the old value after.
struct ScopedEnv {
    std::string name, old;
    bool had;
    ScopedEnv(const char* n, const char* value) : name(n) {
        const char* o = std::getenv(n);
        had = o != nullptr;
        if (had) old = o;
        ::setenv(n, value, 1);
    }
    ~ScopedEnv() {
        if (had) ::setenv(name.c_str(), old.c_str(), 1);
        else ::unsetenv(name.c_str());
    }
};

const char* four_quads_obj =
    "mtllib scene.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\n"
    "v 0 1 0\nv 1 1 0\nv 1 1 1\nv 0 1 1\n"
    "f 1 2 3 4\n"          // before any usemtl: the default material
    "usemtl red\nf 5 6 7\n"
    "usemtl chrome\nf 5 7 8\n"
    "usemtl lamp\nf 1 3 7\n"
    "usemtl plastic\nf 2 3 7\n"
    "usemtl nosuch\nf 4 3 7\n";

const char* scene_mtl =
    "newmtl red\nKd 0.8 0.1 0.05\n"
    "newmtl chrome\nKd 0 0 0\nKs 0.9 0.85 0.8\nillum 3\n"
    "newmtl lamp\nKd 0.5 0.5 0.5\nKe 4 3 2\n"
    "newmtl plastic\nKd 0.2 0.3 0.4\nKs 0.5 0.5 0.5\nillum 2\n";

}  // namespace

TEST_CASE("materials: Kd, Ks with illum 3..7 as a mirror, and Ke come from the MTL file, per triangle") {
    const TempDir dir("arbor-mtl");
    dir.write("scene.obj", four_quads_obj);
    dir.write("scene.mtl", scene_mtl);
    engine::Warnings w;
    const engine::Mesh m = engine::load_obj((dir.path / "scene.obj").string(), w);
    CHECK(w.lines.empty());
    REQUIRE(m.triangle_count() == 7);
    REQUIRE(m.material.size() == 7);
    auto mat = [&](std::size_t t) -> const engine::Material& { return m.materials.at(m.material[t]); };
    CHECK(mat(0).name == "default");
    CHECK(mat(1).name == "default");
    CHECK(mat(2).name == "red");
    CHECK(mat(2).diffuse.x == doctest::Approx(0.8f));
    CHECK(mat(2).diffuse.z == doctest::Approx(0.05f));
    CHECK(engine::is_black(mat(2).mirror));
    CHECK(mat(3).name == "chrome");
    CHECK(mat(3).mirror.y == doctest::Approx(0.85f));
    CHECK(engine::is_black(mat(3).diffuse));
    CHECK(mat(4).name == "lamp");
    CHECK(mat(4).emission.x == doctest::Approx(4.0f));
    CHECK(mat(4).emission.z == doctest::Approx(2.0f));
    CHECK(mat(5).name == "plastic");
    CHECK(engine::is_black(mat(5).mirror));  // illum 2: a highlight, not a mirror; ignored
    CHECK(mat(6).name == "default");          // unknown usemtl name

    // An emissive material makes its triangle an area light; no point light is added.
    const engine::Scene s = engine::scene_from_mesh(m, "scene");
    CHECK(s.lights.empty());
    const engine::LightSet lights(s);
    CHECK(lights.emitter_count() == 1);
    engine::RenderSettings set;
    set.integrator = engine::IntegratorKind::path;
    const auto plan = engine::make_plan(s, lights, set);
    CHECK(plan.area_shadows);
    CHECK_FALSE(plan.point_shadows);
    CHECK(plan.mirror);
    CHECK(plan.emission);
}

TEST_CASE("materials: negative, non-finite and above-one values are clamped with a warning") {
    const TempDir dir("arbor-mtl-bad");
    dir.write("bad.obj", "mtllib bad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl odd\nf 1 2 3\n");
    dir.write("bad.mtl", "newmtl odd\nKd -0.5 1.5 nan\nKs 2 0.5 -1\nillum 5\nKe inf -3 2\n");
    engine::Warnings w;
    const engine::Mesh m = engine::load_obj((dir.path / "bad.obj").string(), w);
    REQUIRE(m.material.size() == 1);
    const engine::Material& mat = m.materials.at(m.material[0]);
    CHECK(mat.diffuse.x == 0.0f);
    CHECK(mat.diffuse.y == 1.0f);
    CHECK(mat.diffuse.z == 0.0f);
    CHECK(mat.mirror.x == 1.0f);
    CHECK(mat.mirror.y == doctest::Approx(0.5f));
    CHECK(mat.mirror.z == 0.0f);
    CHECK(mat.emission.x == 0.0f);
    CHECK(mat.emission.y == 0.0f);
    CHECK(mat.emission.z == doctest::Approx(2.0f));
    REQUIRE(w.lines.size() == 1);
    CHECK(w.lines[0].find("odd") != std::string::npos);
}

TEST_CASE("scene_from_mesh: a model without emitters gets one point light, the framing shows the whole box") {
    const engine::Mesh box = engine::make_box({10, -2, 3}, {14, 5, 4});
    const engine::Scene s = engine::scene_from_mesh(box, "box");
    REQUIRE(s.lights.size() == 1);
    CHECK(s.lights[0].position.y > box.bounds.hi.y);
    const int w = 64, h = 48;
    engine::Camera cam = s.camera;
    cam.prepare(w, h);
    // Every corner of the bounds is in front of the camera and projects inside the image.
    const Vec3f view = cam.look_at - cam.eye;
    for (int c = 0; c < 8; ++c) {
        const Vec3f p{c & 1 ? box.bounds.hi.x : box.bounds.lo.x, c & 2 ? box.bounds.hi.y : box.bounds.lo.y,
                      c & 4 ? box.bounds.hi.z : box.bounds.lo.z};
        CHECK(simd::dot(p - cam.eye, view) > 0.0f);
        // Pixel coordinates of p: solve eye + (corner + du*px + dv*py) * t = p through the camera's rays.
        const accel::Ray r00 = cam.ray(0, 0), r10 = cam.ray(1, 0), r01 = cam.ray(0, 1);
        const Vec3f du = r10.dir - r00.dir, dv = r01.dir - r00.dir;
        const Vec3f fwd = simd::cross(du, dv);  // along the view axis
        const Vec3f d = p - cam.eye;
        const float t = simd::dot(r00.dir, fwd) / simd::dot(d, fwd);  // scales d onto the image plane
        const Vec3f q = d * t - r00.dir;
        const float px = simd::dot(q, du) / simd::dot(du, du), py = simd::dot(q, dv) / simd::dot(dv, dv);
        CAPTURE(c);
        CHECK(px >= 0.0f);
        CHECK(px <= float(w));
        CHECK(py >= 0.0f);
        CHECK(py <= float(h));
    }
}

TEST_CASE("built-in scenes: default, cornell (procedural model without ../shared), scaling") {
    const auto d = engine::make_builtin_scene("builtin:default");
    CHECK(d.lights.size() == 1);
    CHECK(engine::scene_traits(d, engine::LightSet(d)).mirror);

    {
        const ScopedEnv env("ARBOR_SHARED_SCENES", "/nonexistent/arbor-shared");
        const auto c = engine::make_builtin_scene("builtin:cornell");
        const engine::LightSet lights(c);
        CHECK(c.lights.empty());
        CHECK(lights.emitter_count() == 2);  // the ceiling light quad
        const auto t = engine::scene_traits(c, lights);
        CHECK(t.mirror);
        CHECK(t.emissive);
        CHECK(c.mesh.triangle_count() == 12 + 20 * 256 + 20 * 256);  // 6 quads, icosphere model, mirror sphere
        // The model stands on the floor inside the box.
        CHECK(c.mesh.bounds.lo.y == doctest::Approx(0.0f));
        CHECK(c.mesh.bounds.hi.y <= 2.0f);

        const auto sc = engine::make_builtin_scene("builtin:scaling:2");
        CHECK(sc.mesh.triangle_count() == 2 + 4 * 20 * 4096);
        CHECK(sc.lights.size() == 1);
    }
    const std::string bunny = engine::shared_models_dir() + "/stanford-bunny.obj";
    if (std::filesystem::exists(bunny)) {
        const auto c = engine::make_builtin_scene("builtin:cornell");
        CHECK(c.mesh.triangle_count() == 12 + 69451 + 20 * 256);
    }
    CHECK_THROWS_AS(engine::make_builtin_scene("builtin:nope"), engine::InputError);
    CHECK_THROWS_AS(engine::make_builtin_scene("builtin:scaling:0"), engine::InputError);
}
