#include "testing.h"

#include "engine/obj_loader.h"
#include "engine/procedural.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace arbor::testing {

std::string shared_scenes_dir() {
    const std::string dir = ARBOR_SHARED_SCENES;
    // The tests on real models must not pass by skipping them: a missing ../shared is a failure.
    REQUIRE_MESSAGE(std::filesystem::is_directory(dir), "shared scenes not found at " << dir
                                                        << " (ARBOR_SHARED_SCENES): the real-model tests need them");
    return dir;
}

std::vector<std::string> model_paths() {
    std::vector<std::string> out;
    const std::string dir = shared_scenes_dir() + "/models";
    REQUIRE_MESSAGE(std::filesystem::is_directory(dir), dir << " not found: the real-model tests need it");
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.path().extension() == ".obj") out.push_back(e.path().string());
    REQUIRE_MESSAGE(!out.empty(), "no .obj model in " << dir);
    std::sort(out.begin(), out.end());
    return out;
}

void for_each_shared_mesh(const std::function<void(const std::string& path, const engine::Mesh& mesh)>& f) {
    const auto paths = model_paths();
    REQUIRE_MESSAGE(paths.size() >= 10, "the shared models (../shared/scenes/models) are needed");
    for (const auto& path : paths) {
        CAPTURE(path);
        engine::Warnings w;
        f(path, engine::load_obj(path, w));
    }
}

namespace {
Vec3f random_in(const accel::Bounds& b, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    return {b.lo.x + u(rng) * (b.hi.x - b.lo.x), b.lo.y + u(rng) * (b.hi.y - b.lo.y), b.lo.z + u(rng) * (b.hi.z - b.lo.z)};
}
Vec3f random_dir(std::mt19937& rng) {
    std::normal_distribution<float> n(0.0f, 1.0f);
    Vec3f d{n(rng), n(rng), n(rng)};
    return simd::normalize(d);
}
}  // namespace

std::vector<Ray> random_rays_into(const accel::Bounds& b, std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    const Vec3f c = b.center();
    const float r = simd::length(b.extent()) * 0.5f + 1e-3f;
    std::vector<Ray> rays(n);
    for (auto& ray : rays) {
        ray.org = c + random_dir(rng) * (2.0f * r);
        ray.dir = random_in(b, rng) - ray.org;
        ray.tnear = 0.0f;
        ray.tfar = INFINITY;
    }
    return rays;
}

std::vector<Ray> random_rays_inside(const accel::Bounds& b, std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<Ray> rays(n);
    for (auto& ray : rays) {
        ray.org = random_in(b, rng);
        ray.dir = random_dir(rng);
        ray.tnear = 0.0f;
        ray.tfar = INFINITY;
    }
    return rays;
}

std::vector<Ray> camera_rays(const accel::Bounds& b, int width, int height) {
    const Vec3f c = b.center();
    const float r = simd::length(b.extent()) * 0.5f + 1e-3f;
    const Vec3f eye = c + Vec3f{0.3f, 0.4f, 1.0f} * (2.5f * r);
    const Vec3f fwd = simd::normalize(c - eye);
    const Vec3f right = simd::normalize(simd::cross(fwd, Vec3f{0, 1, 0}));
    const Vec3f up = simd::cross(right, fwd);
    std::vector<Ray> rays;
    rays.reserve(std::size_t(width) * std::size_t(height));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const float px = (float(x) + 0.5f) / float(width) - 0.5f, py = (float(y) + 0.5f) / float(height) - 0.5f;
            rays.push_back({eye, 0.0f, fwd + right * (0.8f * px) - up * (0.8f * py), INFINITY});
        }
    return rays;
}

std::vector<Ray> three_kinds(const accel::Bounds& b, std::size_t n, std::uint32_t seed) {
    std::vector<Ray> rays = random_rays_into(b, n, seed);
    const auto inside = random_rays_inside(b, n, seed + 1);
    const int side = std::max(8, int(std::sqrt(double(n))));
    const auto camera = camera_rays(b, side, side);
    rays.insert(rays.end(), inside.begin(), inside.end());
    rays.insert(rays.end(), camera.begin(), camera.end());
    return rays;
}

engine::Mesh procedural_shapes() {
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.2f, 9);
    mesh.append(engine::make_torus({1.5f, 0.2f, -0.3f}, 1.0f, 0.25f, 32, 12));
    mesh.append(engine::make_box({-3, -1.2f, -3}, {3, -1.1f, 3}));
    return mesh;
}

std::size_t count_disagreements(const std::vector<Hit>& a, const std::vector<Hit>& b) {
    std::size_t bad = 0;
    for (std::size_t i = 0; i < a.size(); ++i) bad += !accel::hits_agree(a[i], b[i]);
    return bad;
}

std::size_t count_occlusion_disagreements(const std::vector<Hit>& any, const std::vector<Hit>& closest) {
    std::size_t bad = 0;
    for (std::size_t i = 0; i < any.size(); ++i) bad += any[i].is_hit() != closest[i].is_hit();
    return bad;
}

void place(engine::Mesh& mesh, float offset, float scale) {
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
        mesh.x[i] = mesh.x[i] * scale + offset;
        mesh.y[i] = mesh.y[i] * scale - offset;
        mesh.z[i] = mesh.z[i] * scale + 0.5f * offset;
    }
    mesh.compute_bounds();
}

}  // namespace arbor::testing
