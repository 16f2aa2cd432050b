// The cost integrator: per-pixel nodes visited and triangles tested equal counts worked out by
// hand on a two-triangle scene for every structure (the trees are checked first, so a builder
// change says why a count moved); the image is the same with 1 and 2 threads; the statistics mode
// refuses a structure built without the layout it counts on.
#include "accel/factory/make_accel.h"
#include "accel/interface/accel.h"
#include "accel/structures/kdtree_accel.h"
#include "engine/renderer.h"
#include "engine/tracer.h"
#include "render_scenes.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <numbers>

using namespace arbor;

namespace {

/// Triangle A around x = -5 at z = 0, triangle B around x = +5 at z = -1; a camera at z = 10
/// looking down -z whose five pixel centres (image 5 x 1, no jitter) aim at x = -10, -5, 0, 5, 10
/// on the plane z = 0: outside the scene, on A, between A and B, on B, outside.
engine::Scene two_triangles() {
    engine::Scene s;
    s.mesh.x = {-6, -4, -5, 4, 6, 5};
    s.mesh.y = {-1, -1, 1, -1, -1, 1};
    s.mesh.z = {0, 0, 0, -1, -1, -1};
    s.mesh.indices = {0, 1, 2, 3, 4, 5};
    s.mesh.compute_bounds();
    s.camera.eye = {0, 0, 10};
    s.camera.look_at = {0, 0, 0};
    s.camera.up = {0, 1, 0};
    s.camera.vfov_degrees = float(2.0 * std::atan(0.25) * 180.0 / std::numbers::pi);  // 5 units per pixel at z = 0
    return s;
}

engine::RenderSettings cost_settings(int w, int h, int spp, bool jitter) {
    engine::RenderSettings set;
    set.width = w, set.height = h, set.spp = spp, set.tile = 4, set.jitter = jitter;
    set.integrator = engine::IntegratorKind::cost;
    return set;
}

engine::Image cost_image(const engine::Scene& s, const accel::Accel& a, const engine::RenderSettings& set, int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    return engine::render(s, a, set);
}

accel::BuildConfig fine_build() {
    accel::BuildConfig cfg;
    cfg.bvh.max_leaf_size = 1;
    cfg.kd.traversal_cost = 0.25f;  // so that the kd-tree splits two triangles at all
    cfg.layouts = accel::Layouts::all;
    return cfg;
}

void check_row(const engine::Image& img, const int (&nodes)[5], const int (&tris)[5]) {
    REQUIRE(img.names == std::vector<std::string>{"nodes", "tris"});
    for (int x = 0; x < 5; ++x) {
        CAPTURE(x);
        CHECK(img.at(0, x, 0) == float(nodes[x]));
        CHECK(img.at(1, x, 0) == float(tris[x]));
    }
}

}  // namespace

TEST_CASE("cost: brute visits its one node and tests every triangle for every ray") {
    const auto s = two_triangles();
    const auto a = accel::make_accel(accel::AccelKind::brute, s.mesh.view(), fine_build());
    check_row(cost_image(s, *a, cost_settings(5, 1, 1, false), 1), {1, 1, 1, 1, 1}, {2, 2, 2, 2, 2});
}

TEST_CASE("cost: the BVHs count the root's box test, the leaf entered and its triangle, by hand") {
    // Each BVH of two triangles with leaf size 1: a root holding the two leaves. A ray through A or
    // B tests the root's two child boxes (1 node) and enters one leaf (1 node, 1 triangle); the ray
    // between them tests the root's child boxes and enters nothing; the outer rays miss the scene
    // box, which is tested before the root and not counted.
    const auto s = two_triangles();
    for (auto kind : {accel::AccelKind::bvh_median, accel::AccelKind::bvh_sah, accel::AccelKind::lbvh}) {
        CAPTURE(accel::to_string(kind));
        const auto a = accel::make_accel(kind, s.mesh.view(), fine_build());
        REQUIRE(a->stats().nodes == 3);
        REQUIRE(a->stats().leaves == 2);
        check_row(cost_image(s, *a, cost_settings(5, 1, 1, false), 1), {0, 2, 1, 2, 0}, {0, 1, 0, 1, 0});
    }
}

TEST_CASE("cost: the kd-tree counts split planes passed and leaves entered, by hand") {
    const auto s = two_triangles();
    const auto kd_built = accel::make_kdtree_accel(s.mesh.view(), fine_build());
    const accel::KdTreeAccel& kd = *kd_built;
    // The tree: x < -4 holds A; else x < 4 is an empty leaf, x >= 4 holds B.
    const auto& n = kd.tree().nodes;
    REQUIRE(n.size() == 5);
    REQUIRE((!n[0].is_leaf() && n[0].axis() == 0 && n[0].split == -4.0f && n[0].index() == 2));
    REQUIRE((n[1].is_leaf() && kd.tree().leaves[n[1].index()].count == 1));
    REQUIRE((!n[2].is_leaf() && n[2].axis() == 0 && n[2].split == 4.0f && n[2].index() == 4));
    REQUIRE((n[3].is_leaf() && kd.tree().leaves[n[3].index()].count == 0));
    REQUIRE((n[4].is_leaf() && kd.tree().leaves[n[4].index()].count == 1));
    // On A: the root's plane, then A's leaf. Between: both planes and the empty leaf. On B: both
    // planes and B's leaf. The outer rays miss the scene box.
    check_row(cost_image(s, kd, cost_settings(5, 1, 1, false), 1), {0, 2, 3, 3, 0}, {0, 1, 0, 1, 0});
}

TEST_CASE("cost: the image is the same with 1 and 2 threads and averages the samples") {
    const auto s = testing::small_scene();
    for (auto kind : {accel::AccelKind::bvh_sah, accel::AccelKind::kdtree}) {
        CAPTURE(accel::to_string(kind));
        const auto a = accel::make_accel(kind, s.mesh.view(), fine_build());
        const auto set = cost_settings(24, 18, 3, true);
        const auto one = cost_image(s, *a, set, 1), two = cost_image(s, *a, set, 2);
        CHECK(one.planes == two.planes);
        // Means of three integer counts: a multiple of 1/3, and some pixel actually costs something.
        float most = 0;
        for (float v : one.planes[0]) {
            CHECK(std::fabs(v * 3.0f - std::round(v * 3.0f)) < 1e-4f);
            most = std::max(most, v);
        }
        CHECK(most >= 2.0f);
    }
}

TEST_CASE("cost: a structure without its counting layout is refused, and the plans name their layers") {
    const auto s = two_triangles();
    accel::BuildConfig cfg = fine_build();
    cfg.layouts = accel::Layouts::simd;
    const auto a = accel::make_accel(accel::AccelKind::bvh_sah, s.mesh.view(), cfg);
    CHECK_THROWS_AS(cost_image(s, *a, cost_settings(5, 1, 1, false), 1), std::logic_error);
    // The plan of a cost render says what it writes; a primary render's plan is unchanged.
    engine::RenderSettings set = cost_settings(5, 1, 1, false);
    const engine::LightSet lights(s);
    CHECK(engine::make_plan(s, lights, set).line("x").find("layers: nodes tris") != std::string::npos);
    set.integrator = engine::IntegratorKind::primary;
    CHECK(engine::channel_names(engine::make_plan(s, lights, set)) ==
          std::vector<std::string>{"R", "G", "B", "Z", "N.X", "N.Y", "N.Z", "A.R", "A.G", "A.B"});
}

TEST_CASE("cost: the counted walk finds the normal paths' hits bit for bit") {
    // The counts are those of the rays the render traces: the counting loop answers exactly as the
    // packet path the renderer uses for camera rays (t, prim, u, v).
    const auto s = testing::small_scene();
    engine::Camera cam = s.camera;
    cam.prepare(32, 24);
    std::vector<accel::Ray> rays;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 32; ++x) rays.push_back(cam.ray(float(x) + 0.5f, float(y) + 0.5f));
    for (auto kind : {accel::AccelKind::brute, accel::AccelKind::bvh_median, accel::AccelKind::bvh_sah,
                      accel::AccelKind::lbvh, accel::AccelKind::kdtree}) {
        CAPTURE(accel::to_string(kind));
        const auto a = accel::make_accel(kind, s.mesh.view(), fine_build());
        engine::Tracer tracer(*a);
        std::vector<accel::Hit> normal(rays.size()), counted(rays.size());
        std::vector<accel::TraceCounters> cost(rays.size());
        tracer.closest(rays, normal, engine::RenderRayKind::primary);
        REQUIRE(tracer.counted(rays, counted, cost));
        std::size_t hits = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            CAPTURE(i);
            CHECK(std::memcmp(&normal[i], &counted[i], sizeof(accel::Hit)) == 0);
            CHECK(cost[i].rays == 1);
            hits += normal[i].is_hit();
        }
        CHECK(hits > rays.size() / 4);
        CHECK(tracer.counts[std::size_t(engine::RenderRayKind::primary)] == rays.size());  // counted rays are not added
    }
}
