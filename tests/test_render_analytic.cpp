// Known answers: the white furnace, a plane under a point light (inverse-square cosine law per
// pixel), a plane under a square area light (form factor), a closed emissive room
// (L = Le / (1 - albedo)) and the 1/sqrt(spp) convergence of the error.
#include "engine/image_metrics.h"
#include "render_scenes.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

using namespace arbor;
using engine::IntegratorKind;
using engine::Vec3f;

namespace {

/// A sphere of albedo `a` in a uniform environment of radiance L = (0.7, 0.5, 0.3), nothing else.
engine::Scene furnace(float a) {
    engine::Scene s;
    s.mesh = engine::with_material(engine::make_icosphere({0, 0, 0}, 1.0f, 2), testing::diffuse(a, a, a));
    s.background = {0.7f, 0.5f, 0.3f};
    s.camera.eye = {0, 0, 4};
    s.camera.look_at = {0, 0, 0};
    s.camera.vfov_degrees = 40.0f;
    return s;
}

/// Camera inside a closed sphere whose inside emits Le = 1 and reflects with albedo 0.5:
/// the radiance is Le / (1 - a) = 2 in every direction.
engine::Scene closed_room() {
    engine::Scene s;
    const engine::Material wall{"wall", {0.5f, 0.5f, 0.5f}, {}, {1.0f, 1.0f, 1.0f}};
    s.mesh = engine::with_material(engine::make_icosphere({0, 0, 0}, 2.0f, 2), wall);
    s.background = {0, 0, 0};
    s.camera.eye = {0.3f, -0.2f, 0.1f};
    s.camera.look_at = {1, 0.5f, -2};
    s.camera.vfov_degrees = 60.0f;
    return s;
}

/// Standard error of the mean of the image's R channel, taking pixels as independent samples.
double mean_and_stderr(const engine::Image& img, double& stderr_out) {
    const auto& r = img.planes[0];
    double m = 0, m2 = 0;
    for (float v : r) m += v, m2 += double(v) * v;
    m /= double(r.size());
    const double var = m2 / double(r.size()) - m * m;
    stderr_out = std::sqrt(std::max(0.0, var) / double(r.size()));
    return m;
}

}  // namespace

TEST_CASE("white furnace: albedo 1 gives the environment radiance in every pixel, exactly") {
    const auto s = furnace(1.0f);
    auto set = testing::tiny_settings(IntegratorKind::path, 20, 20, 4);
    engine::RenderStats st;
    const auto img = testing::render_brute(s, set, 2, &st);
    for (int c = 0; c < 3; ++c)
        for (float v : img.planes[std::size_t(c)]) REQUIRE(v == doctest::Approx(s.background[c]).epsilon(1e-6));
    CHECK(st.count(engine::RenderRayKind::shadow) == 0);  // no lights, no emitters
    CHECK(st.count(engine::RenderRayKind::diffuse) > 0);
}

TEST_CASE("white furnace: albedo a gives a x L where every sample hits the sphere, L where none does") {
    const float a = 0.4f;
    const auto s = furnace(a);
    auto set = testing::tiny_settings(IntegratorKind::path, 20, 20, 4);
    const auto img = testing::render_brute(s, set);
    // The pixel at the centre sees only the sphere, the corner only the environment.
    for (int c = 0; c < 3; ++c) {
        CHECK(img.at(c, 10, 10) == doctest::Approx(a * s.background[c]).epsilon(1e-6));
        CHECK(img.at(c, 0, 0) == doctest::Approx(s.background[c]).epsilon(1e-6));
        for (float v : img.planes[std::size_t(c)]) {
            REQUIRE(v >= a * s.background[c] * (1 - 1e-6f));
            REQUIRE(v <= s.background[c] * (1 + 1e-6f));
        }
    }
}

TEST_CASE("point light over a plane: the inverse-square cosine law, pixel by pixel") {
    engine::Scene s;
    const float rho = 0.6f, intensity = 10.0f;
    const Vec3f light{0.3f, 2.0f, -0.2f};
    s.mesh = engine::with_material(engine::make_ground(0.0f, 0.0f, 0.0f, 10.0f), testing::diffuse(rho, rho, rho));
    s.lights.push_back({light, Vec3f{intensity}});
    s.background = {0, 0, 0};
    s.camera.eye = {0, 3, 3};
    s.camera.look_at = {0, 0, 0};
    auto set = testing::tiny_settings(IntegratorKind::direct, 24, 16, 1);
    set.jitter = false;
    set.layers = engine::Layers{true, true, true};
    const auto img = testing::render_brute(s, set);
    engine::Camera cam = s.camera;
    cam.prepare(set.width, set.height);
    const int z = img.channel("Z"), ny = img.channel("N.Y"), ar = img.channel("A.R");
    int checked = 0;
    for (int y = 0; y < set.height; ++y)
        for (int x = 0; x < set.width; ++x) {
            const accel::Ray r = cam.ray(float(x) + 0.5f, float(y) + 0.5f);
            const float t = -r.org.y / r.dir.y;
            const Vec3f p = r.org + r.dir * t;
            const Vec3f to = light - p;
            const float d2 = simd::dot(to, to);
            const float expected = rho / std::numbers::pi_v<float> * intensity * (to.y / std::sqrt(d2)) / d2;
            CAPTURE(x);
            CAPTURE(y);
            REQUIRE(img.at(0, x, y) == doctest::Approx(expected).epsilon(1e-4));
            REQUIRE(img.at(z, x, y) == doctest::Approx(t).epsilon(1e-5));
            REQUIRE(img.at(ny, x, y) == doctest::Approx(1.0f));
            REQUIRE(img.at(ar, x, y) == doctest::Approx(rho));
            ++checked;
        }
    CHECK(checked == 24 * 16);
}

TEST_CASE("square area light over a plane: the form factor, by direct and by path") {
    // A 2x2 emitter at height 1 over the origin; the camera looks at the origin through a narrow
    // field of view. Irradiance E = pi Le F with F the form factor of four 1x1 corner rectangles;
    // the reflected radiance is rho Le F.
    const float rho = 0.5f, le = 2.0f, h = 1.0f;
    engine::Scene s;
    s.mesh = engine::with_material(engine::make_ground(0.0f, 0.0f, 0.0f, 10.0f), testing::diffuse(rho, rho, rho));
    s.mesh.append(engine::with_material(engine::make_ground(h, 0.0f, 0.0f, 1.0f), testing::emitter(le)));
    s.mesh.compute_bounds();
    s.background = {0, 0, 0};
    s.camera.eye = {0, 0.5f, 3};
    s.camera.look_at = {0, 0, 0};
    s.camera.vfov_degrees = 0.5f;
    const double x = 1.0 / h, y = 1.0 / h;
    const double corner = (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
                           y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) / (2 * std::numbers::pi);
    const double expected = rho * le * 4 * corner;
    for (IntegratorKind k : {IntegratorKind::direct, IntegratorKind::path}) {
        CAPTURE(engine::to_string(k));
        const auto img = testing::render_brute(s, testing::tiny_settings(k, 8, 8, 256));
        double se = 0;
        const double m = mean_and_stderr(img, se);
        CHECK(se > 0.0);
        CHECK(std::fabs(m - expected) < 5 * se + 2e-3 * expected);
    }
}

TEST_CASE("closed emissive room: L = Le / (1 - a), and the error falls as 1/sqrt(spp)") {
    const auto s = closed_room();
    auto set = testing::tiny_settings(IntegratorKind::path, 16, 16, 4);
    set.max_depth = 64;
    engine::Image exact(16, 16, {"R", "G", "B"});
    for (auto& p : exact.planes) std::fill(p.begin(), p.end(), 2.0f);
    double rmse[2];
    const int spp[2] = {4, 64};
    for (int i = 0; i < 2; ++i) {
        set.spp = spp[i];
        const auto img = testing::render_brute(s, set);
        double se = 0;
        const double m = mean_and_stderr(img, se);
        CAPTURE(spp[i]);
        CHECK(std::fabs(m - 2.0) < 5 * se);
        rmse[i] = engine::compare_rgb(img, exact).rmse;
    }
    // 16x the samples: a quarter of the error, within a factor of 1.5.
    const double ratio = rmse[0] / rmse[1];
    CAPTURE(ratio);
    CHECK(ratio > 4.0 / 1.5);
    CHECK(ratio < 4.0 * 1.5);
}
