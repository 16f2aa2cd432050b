// Smooth shading (engine/shading.h, engine/smooth_normals.h): vertex normals interpolated with the
// hit's barycentrics, smooth normals computed with a crease angle (and across unwelded copies of a
// vertex, as STL files have them), the shadow terminator of a coarse sphere (Hanika 2021: no black
// band where the shading normal faces the light), and textures looked up the right way up.
#include "engine/shading.h"
#include "engine/smooth_normals.h"
#include "render_scenes.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace arbor;
using engine::Vec3f;

namespace {

/// Every triangle with its own three vertices, as an STL file has them.
engine::Mesh unwelded(const engine::Mesh& m) {
    engine::Mesh out;
    const auto v = m.view();
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        const std::uint32_t a = out.add_vertex(v.corner(t, 0)), b = out.add_vertex(v.corner(t, 1)), c = out.add_vertex(v.corner(t, 2));
        out.add_triangle(a, b, c);
    }
    out.compute_bounds();
    return out;
}

float angle_degrees(const Vec3f& a, const Vec3f& b) {
    return std::acos(std::clamp(simd::dot(simd::normalize(a), simd::normalize(b)), -1.0f, 1.0f)) * 57.29578f;
}

}  // namespace

TEST_CASE("smooth normals: a sphere's corners point outward, a box keeps its edges, STL copies are joined") {
    const Vec3f c{0.3f, -0.2f, 1.0f};
    for (const bool weld : {true, false}) {
        CAPTURE(weld);
        engine::Mesh sphere = engine::make_icosphere(c, 2.0f, 2);
        if (!weld) sphere = unwelded(sphere);
        CHECK(engine::compute_smooth_normals(sphere) == 3 * sphere.triangle_count());
        REQUIRE(sphere.has_normals());
        float worst = 0.0f;
        for (std::size_t k = 0; k < sphere.indices.size(); ++k) {
            const std::uint32_t v = sphere.indices[k];
            worst = std::max(worst, angle_degrees(sphere.normals[sphere.normal_index[k]], Vec3f{sphere.x[v], sphere.y[v], sphere.z[v]} - c));
        }
        CHECK(worst < 1.0f);  // on the unit sphere the mean of the faces around a vertex is radial
        // Corners at one position share one normal (the welded and the unwelded mesh alike).
        CHECK(sphere.normals.size() == 162);
    }
    engine::Mesh box = engine::make_box({0, 0, 0}, {1, 2, 3});
    engine::compute_smooth_normals(box);
    const auto v = box.view();
    for (std::size_t t = 0; t < box.triangle_count(); ++t) {
        const Vec3f face = simd::cross(v.corner(t, 1) - v.corner(t, 0), v.corner(t, 2) - v.corner(t, 0));
        for (int k = 0; k < 3; ++k) CHECK(angle_degrees(box.normals[box.normal_index[3 * t + std::size_t(k)]], face) < 1e-3f);
    }
    // Corners that already have a normal keep it.
    engine::Mesh tri;
    tri.add_vertex({0, 0, 0}), tri.add_vertex({1, 0, 0}), tri.add_vertex({0, 1, 0});
    tri.normals = {{0.6f, 0.0f, 0.8f}};
    engine::CornerAttributes a;
    a.normal[0] = 0;
    tri.add_triangle(0, 1, 2, 0, a);
    CHECK(engine::compute_smooth_normals(tri) == 2);
    CHECK(tri.normal_index[0] == 0);
    CHECK(tri.normals[tri.normal_index[1]].z == doctest::Approx(1.0f));
}

TEST_CASE("shading normal: barycentric interpolation, turned to the side the ray came from") {
    engine::Mesh m;
    m.add_vertex({0, 0, 0}), m.add_vertex({1, 0, 0}), m.add_vertex({0, 1, 0});
    m.normals = {simd::normalize(Vec3f{-1, 0, 1}), simd::normalize(Vec3f{1, 0, 1}), Vec3f{0, 0, 1}};
    engine::CornerAttributes a;
    a.normal[0] = 0, a.normal[1] = 1, a.normal[2] = 2;
    m.add_triangle(0, 1, 2, 0, a);
    const Vec3f up{0, 0, 1};
    const Vec3f at0 = engine::shading_normal(m, 0, engine::barycentrics(0, 0), up);
    CHECK(at0.x == doctest::Approx(-0.70710678f));
    const Vec3f mid = engine::shading_normal(m, 0, engine::barycentrics(0.5f, 0), up);  // halfway 0 -> 1
    CHECK(mid.x == doctest::Approx(0.0f).epsilon(1e-6));
    CHECK(mid.z == doctest::Approx(1.0f));
    // Seen from below, every normal is turned down with the geometric one.
    CHECK(engine::shading_normal(m, 0, engine::barycentrics(0.2f, 0.2f), -up).z < 0.0f);
    // Hanika's point: lifted above the flat triangle where the corners' planes bend over it, the
    // hit point itself at a corner.
    CHECK(engine::terminator_point(m, 0, engine::barycentrics(0.5f, 0), {0.5f, 0, 0}, up).z > 0.0f);
    const Vec3f corner = engine::terminator_point(m, 0, engine::barycentrics(0, 0), {0, 0, 0}, up);
    CHECK(corner.z == 0.0f);
    CHECK(engine::above_surface({0.3f, 0.0f, -0.4f}, up).z == doctest::Approx(0.4f));
}

TEST_CASE("shading: a coarse smooth sphere has no black terminator band where its normals face the light") {
    // An icosahedron (20 faces) with smooth normals, lit from the side by a far point light: the
    // worst case for the terminator. Pixels whose shading normal faces the light (cos > 0.25) must
    // be lit; a shadow ray leaving the flat face (no lift) hits the neighbouring faces there.
    engine::Scene s;
    s.mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 0);
    engine::compute_smooth_normals(s.mesh, 90.0f);
    s.mesh.compute_bounds();
    s.camera.eye = {0, 0, 6};
    s.camera.look_at = {0, 0, 0};
    s.camera.vfov_degrees = 25.0f;
    const Vec3f light_dir = simd::normalize(Vec3f{1.0f, 0.3f, 0.2f});
    s.lights.push_back({light_dir * 1000.0f, Vec3f{1e6f}});
    s.background = {0, 0, 0};
    auto set = testing::tiny_settings(engine::IntegratorKind::direct, 96, 96, 1);
    set.jitter = false;
    set.layers = engine::Layers{false, true, false};
    const engine::Image img = testing::render_brute(s, set);
    const int nx = img.channel("N.X");
    std::size_t facing = 0, black = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const Vec3f n{img.at(nx, x, y), img.at(nx + 1, x, y), img.at(nx + 2, x, y)};
            if (!(simd::dot(n, light_dir) > 0.25f)) continue;
            ++facing;
            black += img.at(0, x, y) <= 0.0f;
        }
    MESSAGE("terminator: " << black << " black of " << facing << " pixels whose shading normal faces the light");
    CHECK(facing > 1000);
    CHECK(black == 0);
}

TEST_CASE("shading: a textured quad shows its image the right way up, in linear colour") {
    // A quad facing the camera, v = 1 at its top; the texture's top row is red, its bottom blue.
    engine::Scene s;
    for (const Vec3f& p : {Vec3f{-1, -1, 0}, Vec3f{1, -1, 0}, Vec3f{1, 1, 0}, Vec3f{-1, 1, 0}}) s.mesh.add_vertex(p);
    s.mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    engine::CornerAttributes a;
    a.uv[0] = 0, a.uv[1] = 1, a.uv[2] = 2;
    s.mesh.add_triangle(0, 1, 2, 0, a);
    a.uv[0] = 0, a.uv[1] = 2, a.uv[2] = 3;
    s.mesh.add_triangle(0, 2, 3, 0, a);
    engine::Texture t;
    t.width = 1, t.height = 8;
    for (int row = 0; row < 8; ++row)  // top half red; bottom half sRGB 188 blue (linear about 0.5)
        t.texels.insert(t.texels.end(), {std::uint8_t(row < 4 ? 255 : 0), 0, std::uint8_t(row < 4 ? 0 : 188)});
    s.mesh.textures.push_back(t);
    engine::Material m{"tex", {1, 1, 1}, {}, {}};
    m.diffuse_texture = 0;
    s.mesh.materials = {m};
    s.mesh.compute_bounds();
    s.camera.eye = {0, 0, 3};
    s.camera.look_at = {0, 0, 0};
    s.background = {0, 0, 0};
    auto set = testing::tiny_settings(engine::IntegratorKind::primary, 16, 16, 1);
    set.jitter = false;
    set.layers = engine::Layers{false, false, true};
    const engine::Image img = testing::render_brute(s, set);
    const int ar = img.channel("A.R");
    CHECK(img.at(ar, 8, 6) == doctest::Approx(1.0f));      // upper half: red
    CHECK(img.at(ar + 2, 8, 6) == doctest::Approx(0.0f));
    CHECK(img.at(ar + 2, 8, 10) == doctest::Approx(0.5f).epsilon(0.01));  // lower half: blue, linear
    CHECK(img.at(ar, 8, 10) == doctest::Approx(0.0f));
}
