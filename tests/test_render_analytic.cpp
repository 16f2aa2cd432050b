// Known answers: the white furnace, a plane under a point light (inverse-square cosine law per
// pixel), a plane under a square area light (form factor), a closed emissive room
// (L = Le / (1 - albedo)), the 1/sqrt(spp) convergence of the per-pixel error and of the image mean.
// Each image is rendered with brute force and with bvh-sah on its packet path and on its single-ray
// path, bit-identical (testing::render_all_paths), so every known answer holds on all three.
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

/// A 2x2 emitter (Le = 2) at height 1 over a ground plane of albedo 0.5; the camera looks at the
/// origin through a narrow field of view. Irradiance E = pi Le F with F the form factor of four 1x1
/// corner rectangles; the reflected radiance is rho Le F (area_light_expected).
engine::Scene area_light_scene() {
    engine::Scene s;
    s.mesh = engine::with_material(engine::make_ground(0.0f, 0.0f, 0.0f, 10.0f), testing::diffuse(0.5f, 0.5f, 0.5f));
    s.mesh.append(engine::with_material(engine::make_ground(1.0f, 0.0f, 0.0f, 1.0f), testing::emitter(2.0f)));
    s.mesh.compute_bounds();
    s.background = {0, 0, 0};
    s.camera.eye = {0, 0.5f, 3};
    s.camera.look_at = {0, 0, 0};
    s.camera.vfov_degrees = 0.5f;
    return s;
}

double corner_form_factor(double x, double y) {
    return (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
            y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) / (2 * std::numbers::pi);
}

const double area_light_expected = 0.5 * 2.0 * 4 * corner_form_factor(1.0, 1.0);

}  // namespace

TEST_CASE("white furnace: albedo 1 gives the environment radiance in every pixel, exactly") {
    const auto s = furnace(1.0f);
    auto set = testing::tiny_settings(IntegratorKind::path, 20, 20, 4);
    engine::RenderStats st;
    const auto img = testing::render_all_paths(s, set, 2, &st);
    for (int c = 0; c < 3; ++c)
        for (float v : img.planes[std::size_t(c)]) REQUIRE(v == doctest::Approx(s.background[c]).epsilon(1e-6));
    CHECK(st.count(engine::RenderRayKind::shadow) == 0);  // no lights, no emitters
    CHECK(st.count(engine::RenderRayKind::diffuse) > 0);
}

TEST_CASE("white furnace: albedo a gives a x L where every sample hits the sphere, L where none does") {
    const float a = 0.4f;
    const auto s = furnace(a);
    auto set = testing::tiny_settings(IntegratorKind::path, 20, 20, 4);
    const auto img = testing::render_all_paths(s, set);
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
    const auto img = testing::render_all_paths(s, set);
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
    const auto s = area_light_scene();
    for (IntegratorKind k : {IntegratorKind::direct, IntegratorKind::path}) {
        CAPTURE(engine::to_string(k));
        const auto img = testing::render_all_paths(s, testing::tiny_settings(k, 8, 8, 256));
        double se = 0;
        const double m = mean_and_stderr(img, se);
        CHECK(se > 0.0);
        CHECK(std::fabs(m - area_light_expected) < 5 * se + 2e-3 * area_light_expected);
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
        const auto img = testing::render_all_paths(s, set);
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

TEST_CASE("area light over a plane: the error of the image mean falls as 1/sqrt(spp) over independent seeds") {
    // The mean of an image is itself an estimate of the known radiance; over 64 seeds its
    // root-mean-square error must shrink by sqrt(16) = 4 from 2 to 32 samples per pixel, and the mean
    // of the means must show no bias. (Light sampling here has finite variance; the closed room
    // above does not: next-event estimation between neighbouring faces has a 1/d^2 singularity.)
    const auto s = area_light_scene();
    auto set = testing::tiny_settings(IntegratorKind::direct, 4, 4, 2);
    const int seeds = 64;
    const int spp[2] = {2, 32};
    double rms[2];
    for (int i = 0; i < 2; ++i) {
        set.spp = spp[i];
        double sum2 = 0.0, sum = 0.0;
        for (int k = 0; k < seeds; ++k) {
            set.seed = std::uint32_t(1000 + k);
            double se = 0;
            const double err = mean_and_stderr(testing::render_all_paths(s, set), se) - area_light_expected;
            sum += err;
            sum2 += err * err;
        }
        rms[i] = std::sqrt(sum2 / seeds);
        CAPTURE(spp[i]);
        CHECK(rms[i] > 0.0);
        CHECK(std::fabs(sum / seeds) < 3.0 * rms[i] / std::sqrt(double(seeds)) + 2e-3 * area_light_expected);
    }
    const double ratio = rms[0] / rms[1];
    CAPTURE(ratio);
    CHECK(ratio > 4.0 / 1.4);
    CHECK(ratio < 4.0 * 1.4);
}
