// Scene::update_vertices: after each step of a deforming model, every query (closest hit, any hit,
// all hits, closest point, inside, normals) answers bit for bit as a scene built fresh from the
// new positions, on every structure and with every mode (auto, refit, rebuild); the action and
// reason say what was done; another mesh of the scene keeps its place and ids.
#include "deform.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"
#include "testing.h"

#include <arbor/arbor.h>

#include <doctest/doctest.h>

#include <bit>
#include <cstring>
#include <memory>

using namespace arbor;

namespace {

std::vector<Ray> public_rays(const std::vector<accel::Ray>& in) {
    std::vector<Ray> out(in.size());
    static_assert(sizeof(Ray) == sizeof(accel::Ray));
    std::memcpy(static_cast<void*>(out.data()), in.data(), in.size() * sizeof(Ray));
    return out;
}

bool bits_equal(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }

bool same(const Hit& a, const Hit& b) {
    return bits_equal(a.t, b.t) && a.geom == b.geom && a.prim == b.prim && bits_equal(a.u, b.u) && bits_equal(a.v, b.v);
}

bool same(const ClosestPoint& a, const ClosestPoint& b) {
    bool s = bits_equal(a.distance, b.distance) && a.geom == b.geom && a.prim == b.prim && bits_equal(a.u, b.u) &&
             bits_equal(a.v, b.v);
    for (int k = 0; k < 3; ++k) s = s && bits_equal(a.point[k], b.point[k]);
    return s;
}

/// Every query of `got` against `want` on the same rays and points: the number of answers that differ.
std::size_t differences(const Scene& got, const Scene& want, const std::vector<Ray>& rays, const std::vector<float>& points) {
    std::size_t d = 0;
    const auto h1 = got.intersect(rays), h2 = want.intersect(rays);
    for (std::size_t i = 0; i < rays.size(); ++i) d += !same(h1[i], h2[i]);
    d += got.occluded(rays) != want.occluded(rays);
    constexpr std::size_t max_hits = 8;
    std::vector<Hit> a1(rays.size() * max_hits), a2(a1.size());
    std::vector<std::int32_t> c1(rays.size()), c2(rays.size());
    got.intersect_all(RayArrays::of(rays.data(), rays.size()), max_hits, a1.data(), c1.data());
    want.intersect_all(RayArrays::of(rays.data(), rays.size()), max_hits, a2.data(), c2.data());
    for (std::size_t i = 0; i < a1.size(); ++i) d += !same(a1[i], a2[i]);
    d += c1 != c2;
    const auto p1 = got.closest_point(points), p2 = want.closest_point(points);
    for (std::size_t i = 0; i < p1.size(); ++i) d += !same(p1[i], p2[i]);
    d += got.inside(points) != want.inside(points);
    std::vector<float> n1(3 * rays.size()), n2(n1.size());
    got.hit_normals(h1.data(), h1.size(), sizeof(Hit), n1.data(), 3 * sizeof(float));
    want.hit_normals(h2.data(), h2.size(), sizeof(Hit), n2.data(), 3 * sizeof(float));
    for (std::size_t i = 0; i < n1.size(); ++i) d += !bits_equal(n1[i], n2[i]);
    return d;
}

std::vector<float> grid_points(const engine::Mesh& m, int n) {
    std::vector<float> p;
    const accel::Vec3f lo = m.bounds.lo, e = m.bounds.extent();
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k)
                p.insert(p.end(), {lo.x + e.x * (i + 0.37f) / n, lo.y + e.y * (j + 0.41f) / n, lo.z + e.z * (k + 0.53f) / n});
    return p;
}

}  // namespace

TEST_CASE("update_vertices: a deforming model, every structure and mode, bit for bit as a fresh scene") {
    const engine::Mesh rest = testing::deforming_model();
    engine::Mesh pose;
    testing::deform(rest, pose, 0);
    struct Mode {
        const char* mode;
        double rays;
    };
    // auto with the rays the scene measured, auto told of no rays (refits) and of very many (the
    // loss of every deformed pose outweighs a rebuild), and the two forced modes.
    const Mode modes[] = {{"auto", -1.0}, {"auto", 0.0}, {"auto", 1e15}, {"refit", -1.0}, {"rebuild", -1.0}};
    // The fresh scenes of each step's pose (bvh-sah, or brute for the brute scenes), built once and
    // shared by every structure and mode: the pose of a step is the same for all of them.
    constexpr int steps = 3;
    std::unique_ptr<Scene> fresh_scenes[steps + 1][2];
    const auto fresh_at = [&](int step, bool brute) -> const Scene& {
        std::unique_ptr<Scene>& f = fresh_scenes[step][brute];
        if (!f) {
            f = std::make_unique<Scene>();
            f->add_mesh(testing::packed(pose), pose.indices);
            BuildOptions fo;
            fo.accel = brute ? "brute" : "bvh-sah";
            f->build(fo);
        }
        return *f;
    };
    for (const char* accel_name : {"bvh-sah", "bvh-median", "lbvh", "kdtree", "brute", "auto"}) {
        for (const Mode& mode : modes) {
            CAPTURE(accel_name);
            CAPTURE(mode.mode);
            CAPTURE(mode.rays);
            testing::deform(rest, pose, 0);
            Scene scene;
            scene.add_mesh(testing::packed(pose), pose.indices);
            BuildOptions bo;
            bo.accel = accel_name;
            scene.build(bo);
            const std::string built = scene.accel();
            const bool brute = built == "brute";
            // brute traces every triangle: fewer rays keep the test short.
            const std::size_t n = brute ? 24 : 200;
            for (int step = 1; step <= steps; ++step) {
                CAPTURE(step);
                testing::deform(rest, pose, step);
                UpdateOptions uo;
                uo.mode = mode.mode;
                uo.rays = mode.rays;
                scene.update_vertices(0, testing::packed(pose), uo);
                CHECK(scene.accel() == built);
                const std::string action = scene.update_action();
                CAPTURE(scene.update_reason());
                CHECK(scene.update_reason().rfind(action + ": ", 0) == 0);
                if (built == "kdtree" || std::string(mode.mode) == "rebuild") CHECK(action == "rebuild");
                else if (std::string(mode.mode) == "refit" || (mode.rays == 0.0 && !brute)) CHECK(action == "refit");
                else if (mode.rays > 1e14 && !brute) CHECK(action == "rebuild");
                else CHECK((action == "refit" || action == "rebuild"));
                if (built == "kdtree") CHECK(scene.update_reason().find("split planes") != std::string::npos);
                const Scene& fresh = fresh_at(step, brute);
                float lo[3], hi[3], flo[3], fhi[3];
                scene.bounds(lo, hi), fresh.bounds(flo, fhi);
                for (int k = 0; k < 3; ++k) CHECK((lo[k] == flo[k] && hi[k] == fhi[k]));
                const auto rays = public_rays(testing::three_kinds(pose.bounds, n, 90u + std::uint32_t(step)));
                CHECK(differences(scene, fresh, rays, grid_points(pose, brute ? 3 : 6)) == 0);
            }
        }
    }
}

TEST_CASE("update_vertices: one mesh of two moves, the other keeps its ids and answers") {
    const engine::Mesh sphere = engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.05f, 2);
    engine::Mesh torus = engine::make_torus({2.5f, 0, 0}, 1.0f, 0.3f, 24, 12);
    const engine::Mesh torus_rest = torus;
    for (const char* mode : {"refit", "rebuild", "auto"}) {
        CAPTURE(mode);
        Scene scene;
        REQUIRE(scene.add_mesh(testing::packed(sphere), sphere.indices) == 0);
        REQUIRE(scene.add_mesh(testing::packed(torus_rest), torus_rest.indices) == 1);
        scene.build({"bvh-sah", 0, 0});
        for (int step = 1; step <= 3; ++step) {
            testing::deform(torus_rest, torus, step, 0.1f);
            UpdateOptions uo;
            uo.mode = mode;
            scene.update_vertices(1, testing::packed(torus), uo);
            Scene fresh;
            fresh.add_mesh(testing::packed(sphere), sphere.indices);
            fresh.add_mesh(testing::packed(torus), torus.indices);
            fresh.build({"lbvh", 0, 0});
            engine::Mesh both = sphere;
            both.append(torus);
            both.compute_bounds();
            const auto rays = public_rays(testing::three_kinds(both.bounds, 300, 7u + std::uint32_t(step)));
            CHECK(differences(scene, fresh, rays, grid_points(both, 6)) == 0);
            const auto hits = scene.intersect(rays);
            std::size_t on_torus = 0;
            for (const Hit& h : hits) on_torus += h.geom == 1;
            CHECK(on_torus > 0);
        }
    }
}

TEST_CASE("update_vertices: before the first build, the first query builds over the new positions") {
    const engine::Mesh rest = testing::deforming_model();
    engine::Mesh pose;
    testing::deform(rest, pose, 0);
    Scene scene;
    scene.add_mesh(testing::packed(pose), pose.indices);
    testing::deform(rest, pose, 2);
    scene.update_vertices(0, testing::packed(pose));
    CHECK(scene.update_action() == "none");
    CHECK_FALSE(scene.built());
    Scene fresh;
    fresh.add_mesh(testing::packed(pose), pose.indices);
    const auto rays = public_rays(testing::three_kinds(pose.bounds, 100, 3));
    CHECK(differences(scene, fresh, rays, grid_points(pose, 4)) == 0);
}

TEST_CASE("update_vertices: triangles that were non-finite and are finite now make a rebuild") {
    engine::Mesh m = engine::make_icosphere({0, 0, 0}, 1.0f, 2, 0.0f, 1);
    std::vector<float> p = testing::packed(m);
    const std::vector<float> good = p;
    p[0] = NAN;  // vertex 0: its triangles are left out of the build
    Scene scene;
    scene.add_mesh(p, m.indices);
    scene.build({"bvh-sah", 0, 0});
    UpdateOptions uo;
    uo.mode = "refit";
    scene.update_vertices(0, good, uo);
    CHECK(scene.update_action() == "rebuild");
    CHECK(scene.update_reason().find("non-finite") != std::string::npos);
    Scene fresh;
    fresh.add_mesh(good, m.indices);
    const auto rays = public_rays(testing::three_kinds(m.bounds, 200, 5));
    CHECK(differences(scene, fresh, rays, grid_points(m, 4)) == 0);
}
