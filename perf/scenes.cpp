#include "perf/scenes.h"

#include "accel/util/splitmix64.h"
#include "engine/log.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

namespace arbor::perf {

using engine::Mesh;
using engine::Vec3f;

namespace {

/// splitmix64 stream (accel/util/splitmix64.h): the same numbers on every platform (std
/// distributions are not).
struct Rng : accel::SplitMix64 {
    float range(float lo, float hi) { return lo + (hi - lo) * u01(); }
};

/// Appends the triangles of `src` scaled by `s` and moved by `t`, without materials (cheap for
/// millions of triangles).
void append_geometry(Mesh& dst, const Mesh& src, float s, const Vec3f& t, std::size_t max_triangles = SIZE_MAX) {
    const auto base = std::uint32_t(dst.vertex_count());
    for (std::size_t i = 0; i < src.vertex_count(); ++i) {
        dst.x.push_back(src.x[i] * s + t.x);
        dst.y.push_back(src.y[i] * s + t.y);
        dst.z.push_back(src.z[i] * s + t.z);
    }
    const std::size_t n = std::min(src.triangle_count(), max_triangles);
    for (std::size_t i = 0; i < 3 * n; ++i) dst.indices.push_back(base + src.indices[i]);
}

void add_tri(Mesh& m, const Vec3f& a, const Vec3f& b, const Vec3f& c) {
    const std::uint32_t i = m.add_vertex(a), j = m.add_vertex(b), k = m.add_vertex(c);
    m.indices.insert(m.indices.end(), {i, j, k});
}

void add_quad(Mesh& m, const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& d) {
    add_tri(m, a, b, c);
    add_tri(m, a, c, d);
}

void add_box(Mesh& m, const Vec3f& lo, const Vec3f& hi) { append_geometry(m, engine::make_box(lo, hi), 1.0f, Vec3f{0.0f}); }

engine::Scene finish(Mesh mesh, const std::string& name) {
    mesh.compute_bounds();
    return engine::scene_from_mesh(std::move(mesh), name);
}

}  // namespace

std::size_t mesh_bytes(const Mesh& m) {
    return m.vertex_count() * 3 * sizeof(float) + m.indices.size() * sizeof(std::uint32_t);
}

BenchScene model_scene(const std::string& obj_path) {
    engine::Warnings warnings;
    Mesh mesh = engine::load_obj(obj_path, warnings);
    const std::string name = std::filesystem::path(obj_path).stem().string();
    return {name, "model", engine::scene_from_mesh(std::move(mesh), name), false};
}

BenchScene teapot_in_stadium(const Mesh* model) {
    Mesh dense;
    if (model) {
        dense.x = model->x, dense.y = model->y, dense.z = model->z, dense.indices = model->indices;
    } else {  // stand-in: a bumpy sphere under a torus, ~25k triangles
        dense = engine::make_icosphere({0, 0, 0}, 1.0f, 5, 0.05f, 3);
        append_geometry(dense, engine::make_torus({0, 0.8f, 0}, 0.8f, 0.2f, 64, 32), 1.0f, Vec3f{0.0f});
    }
    dense.compute_bounds();
    // Scale the model to size 1 and stand it on the floor at the origin.
    const Vec3f ext = dense.bounds.extent();
    const float s = 1.0f / std::max(simd::max_component(ext), 1e-6f);
    const Vec3f c = dense.bounds.center();
    Mesh m;
    append_geometry(m, dense, s, Vec3f{-c.x * s, -dense.bounds.lo.y * s, -c.z * s});
    // The stadium: a floor and four walls, 2000 x 200 x 2000, a few big triangles.
    const float h = 1000.0f, wall = 200.0f;
    add_quad(m, {-h, 0, -h}, {-h, 0, h}, {h, 0, h}, {h, 0, -h});
    add_quad(m, {-h, 0, -h}, {h, 0, -h}, {h, wall, -h}, {-h, wall, -h});
    add_quad(m, {-h, 0, h}, {-h, wall, h}, {h, wall, h}, {h, 0, h});
    add_quad(m, {-h, 0, -h}, {-h, wall, -h}, {-h, wall, h}, {-h, 0, h});
    add_quad(m, {h, 0, -h}, {h, 0, h}, {h, wall, h}, {h, wall, -h});
    BenchScene b{"stadium", "stadium", finish(std::move(m), "stadium"), true};
    b.scene.camera.eye = {1.6f, 1.1f, 2.6f};
    b.scene.camera.look_at = {0.0f, 0.35f, 0.0f};
    b.scene.camera.vfov_degrees = 40.0f;
    b.scene.lights.front().position = {2.0f, 8.0f, 3.0f};
    return b;
}

BenchScene architectural_interior(int detail, std::uint64_t seed) {
    Rng rng{seed};
    detail = std::max(detail, 1);
    const float W = 40.0f, H = 8.0f, D = 24.0f;
    Mesh m;
    // The shell: floor, ceiling and walls, two big triangles each.
    add_quad(m, {0, 0, 0}, {0, 0, D}, {W, 0, D}, {W, 0, 0});
    add_quad(m, {0, H, 0}, {W, H, 0}, {W, H, D}, {0, H, D});
    add_quad(m, {0, 0, 0}, {W, 0, 0}, {W, H, 0}, {0, H, 0});
    add_quad(m, {0, 0, D}, {0, H, D}, {W, H, D}, {W, 0, D});
    add_quad(m, {0, 0, 0}, {0, H, 0}, {0, H, D}, {0, 0, D});
    add_quad(m, {W, 0, 0}, {W, 0, D}, {W, H, D}, {W, H, 0});
    for (int i = 1; i < 8; ++i)  // pillars
        for (int k = 1; k < 4; ++k) add_box(m, {5.0f * float(i) - 0.25f, 0, 6.0f * float(k) - 0.25f}, {5.0f * float(i) + 0.25f, H, 6.0f * float(k) + 0.25f});
    for (int i = 0; i < 12 * detail; ++i) {  // partition walls, along x or z
        const float x = rng.range(2, W - 10), z = rng.range(2, D - 10), len = rng.range(4, 9);
        if (rng.u01() < 0.5f) add_box(m, {x, 0, z}, {x + len, 3.0f, z + 0.15f});
        else add_box(m, {x, 0, z}, {x + 0.15f, 3.0f, z + len});
    }
    const Mesh ball = engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.1f, 5);  // 1280 triangles
    for (int i = 0; i < 16 * detail; ++i) {  // tables with objects on them
        const float x = rng.range(1, W - 3), z = rng.range(1, D - 2);
        add_box(m, {x, 0.72f, z}, {x + 1.6f, 0.76f, z + 0.8f});
        for (float dx : {0.05f, 1.5f})
            for (float dz : {0.05f, 0.7f}) add_box(m, {x + dx, 0, z + dz}, {x + dx + 0.05f, 0.72f, z + dz + 0.05f});
        append_geometry(m, ball, rng.range(0.1f, 0.3f), {x + 0.8f, 1.0f, z + 0.4f});
    }
    for (int i = 0; i <= 16; ++i) {  // roof trusses: one big triangle across the whole width each
        const float x = W * float(i) / 16.0f;
        add_tri(m, {x, 5.0f, 0.0f}, {x, 5.0f, D}, {x + 0.1f, H - 0.05f, 0.5f * D});
    }
    for (int i = 0; i < 300 * detail; ++i) {  // long thin diagonal braces from floor to ceiling
        const Vec3f a{rng.range(0, W), 0.01f, rng.range(0, D)}, b{rng.range(0, W), H - 0.01f, rng.range(0, D)};
        add_tri(m, a, b, b + Vec3f{0.05f, 0.0f, 0.05f});
    }
    BenchScene s{"interior", "interior", finish(std::move(m), "interior"), true};
    s.scene.camera.eye = {1.5f, 1.7f, 1.5f};
    s.scene.camera.look_at = {30.0f, 1.5f, 20.0f};
    s.scene.camera.vfov_degrees = 70.0f;
    s.scene.lights.front().position = {20.0f, 7.5f, 12.0f};
    return s;
}

BenchScene grass_field(std::size_t blades, std::uint64_t seed) {
    Rng rng{seed};
    Mesh m;
    add_quad(m, {-10, 0, -10}, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10});
    for (std::size_t i = 0; i < blades; ++i) {
        const Vec3f base{rng.range(-10, 10), 0.0f, rng.range(-10, 10)};
        const float h = rng.range(0.3f, 0.7f), w = h / 40.0f, phi = rng.range(0, 2 * std::numbers::pi_v<float>);
        const Vec3f side{std::cos(phi) * 0.5f * w, 0.0f, std::sin(phi) * 0.5f * w};
        const Vec3f lean{rng.range(-0.3f, 0.3f) * h, h, rng.range(-0.3f, 0.3f) * h};
        add_tri(m, base - side, base + side, base + lean);
    }
    return {"grass", "grass", finish(std::move(m), "grass"), false};
}

BenchScene triangle_soup(std::size_t count, std::uint64_t seed) {
    Rng rng{seed};
    const float s = 1.25f * std::cbrt(1.0f / float(std::max<std::size_t>(count, 1)));
    Mesh m;
    for (std::size_t i = 0; i < count; ++i) {
        const Vec3f c{rng.u01(), rng.u01(), rng.u01()};
        auto corner = [&] { return c + Vec3f{rng.range(-s, s), rng.range(-s, s), rng.range(-s, s)}; };
        const Vec3f a = corner(), b = corner(), d = corner();
        add_tri(m, a, b, d);
    }
    return {"soup", "soup", finish(std::move(m), "soup"), false};
}

BenchScene replicated(std::size_t triangles, std::uint64_t seed) {
    Rng rng{seed};
    const Mesh base = engine::make_icosphere({0, 0, 0}, 0.5f, 4, 0.15f, 11);  // 5120 triangles, size 1
    const std::size_t copies = std::max<std::size_t>(1, (triangles + base.triangle_count() - 1) / base.triangle_count());
    const auto side = std::size_t(std::ceil(std::cbrt(double(copies))));
    Mesh m;
    m.x.reserve(copies * base.vertex_count());
    m.y.reserve(copies * base.vertex_count());
    m.z.reserve(copies * base.vertex_count());
    m.indices.reserve(3 * triangles);
    std::size_t left = triangles;
    for (std::size_t i = 0; i < copies && left > 0; ++i) {
        const Vec3f cell{float(i % side), float((i / side) % side), float(i / (side * side))};
        const Vec3f jitter{rng.range(-0.2f, 0.2f), rng.range(-0.2f, 0.2f), rng.range(-0.2f, 0.2f)};
        const std::size_t n = std::min(left, base.triangle_count());
        append_geometry(m, base, rng.range(0.5f, 1.0f), cell * 1.5f + jitter, n);
        left -= n;
    }
    std::string name = "replicated-" + std::to_string(triangles);
    for (int k = 3; k <= 9; ++k)
        if (triangles == std::size_t(std::pow(10.0, k))) name = "replicated-1e" + std::to_string(k);
    return {name, "replicated", finish(std::move(m), name), false};
}

BenchScene tiny_scene() {
    Mesh m = engine::make_icosphere({0, 0, 0}, 1.0f, 2, 0.1f, 2);  // 320 triangles
    append_geometry(m, engine::make_box({1.2f, -1, -0.5f}, {2.2f, 0.5f, 0.5f}), 1.0f, Vec3f{0.0f});
    add_quad(m, {-3, -1, -3}, {-3, -1, 3}, {3, -1, 3}, {3, -1, -3});
    return {"tiny", "tiny", finish(std::move(m), "tiny"), false};
}

}  // namespace arbor::perf
