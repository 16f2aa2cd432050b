// Sampling helpers: random streams depend only on (seed, pixel, sample, dimension); strata cover
// every cell once; the warps give the densities they claim (means of known integrals).
#include "engine/lights.h"
#include "engine/procedural.h"
#include "engine/sampling.h"
#include "accel/util/splitmix64.h"

#include <doctest/doctest.h>

#include <cmath>
#include <set>

using namespace arbor;
using engine::Vec3f;

TEST_CASE("sampling: the one splitmix64 gives the published sequence") {
    // The first outputs of SplitMix64 seeded with 0 (Vigna's reference splitmix64.c): every
    // stream of the project (rays, samples, jitter, auto's sample, scene hash) rests on these.
    accel::SplitMix64 g;
    CHECK(g.next() == 0xE220A8397B1DCDAFull);
    CHECK(g.next() == 0x6E789E6AA1B965F4ull);
    CHECK(g.next() == 0x06C45D188009454Full);
    CHECK(accel::splitmix64(0) == 0xE220A8397B1DCDAFull);
    CHECK(accel::splitmix64_mix(accel::splitmix64_gamma) == 0xE220A8397B1DCDAFull);
    CHECK(accel::unit_float24(~0ull) < 1.0f);
    CHECK(accel::unit_float24(0) == 0.0f);
}

TEST_CASE("sampling: streams are pure functions of (seed, pixel, sample, dimension)") {
    engine::SampleStream a(7, 123, 4), b(7, 123, 4), c(7, 123, 5), d(8, 123, 4), e(7, 124, 4);
    for (int i = 0; i < 16; ++i) {
        const float x = a.next();
        CHECK(x == b.next());
        CHECK(x >= 0.0f);
        CHECK(x < 1.0f);
        // Neighbouring streams are not copies of each other.
        CHECK(x != c.next());
        CHECK(x != d.next());
        CHECK(x != e.next());
    }
    CHECK(a.dimension() == 16);
    // Uniform enough: the mean and the second moment of 20k draws.
    engine::SampleStream s(1, 2, 3);
    double m1 = 0, m2 = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        const double x = s.next();
        m1 += x, m2 += x * x;
    }
    CHECK(m1 / n == doctest::Approx(0.5).epsilon(0.02));
    CHECK(m2 / n == doctest::Approx(1.0 / 3.0).epsilon(0.02));
}

TEST_CASE("sampling: pixel strata use every cell of an exact grid once, for any sample count") {
    for (int n = 1; n <= 40; ++n) {
        const engine::PixelStrata st(n);
        CHECK(st.cols * st.rows == n);
        CHECK(st.cols <= st.rows);
        std::set<std::pair<int, int>> cells;
        for (int s = 0; s < n; ++s) {
            float x, y;
            st.position(s, 0.999f, 0.001f, x, y);
            REQUIRE(x >= 0.0f);
            REQUIRE(x < 1.0f);
            REQUIRE(y >= 0.0f);
            REQUIRE(y < 1.0f);
            cells.insert({int(x * float(st.cols)), int(y * float(st.rows))});
        }
        CHECK(cells.size() == std::size_t(n));
    }
    CHECK(engine::PixelStrata(16).cols == 4);
    CHECK(engine::PixelStrata(8).cols == 2);
}

TEST_CASE("sampling: cosine hemisphere is unit length, above the surface, with E[cos] = 2/3") {
    const Vec3f normals[] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, simd::normalize(Vec3f{0.3f, -0.8f, 0.2f})};
    for (const Vec3f& n : normals) {
        engine::SampleStream s(3, 1, 0);
        double mean_cos = 0.0;
        const int count = 20000;
        for (int i = 0; i < count; ++i) {
            const float u1 = s.next(), u2 = s.next();
            const Vec3f d = engine::cosine_hemisphere(n, u1, u2);
            REQUIRE(simd::length(d) == doctest::Approx(1.0f).epsilon(1e-4));
            REQUIRE(simd::dot(d, n) >= -1e-6f);
            mean_cos += simd::dot(d, n);
        }
        CHECK(mean_cos / count == doctest::Approx(2.0 / 3.0).epsilon(0.01));
    }
}

TEST_CASE("sampling: uniform triangle points have barycentric mean 1/3 and stay inside") {
    engine::SampleStream s(5, 0, 0);
    double m1 = 0, m2 = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        float b1, b2;
        const float u1 = s.next(), u2 = s.next();
        engine::uniform_triangle(u1, u2, b1, b2);
        REQUIRE(b1 >= 0.0f);
        REQUIRE(b2 >= 0.0f);
        REQUIRE(b1 + b2 <= 1.0f + 1e-6f);
        m1 += b1, m2 += b2;
    }
    CHECK(m1 / n == doctest::Approx(1.0 / 3.0).epsilon(0.02));
    CHECK(m2 / n == doctest::Approx(1.0 / 3.0).epsilon(0.02));
}

TEST_CASE("lights: emitters are picked in proportion to power, pdf = pick / area") {
    engine::Scene scene;
    const engine::Material dim{"dim", {0.5f, 0.5f, 0.5f}, {}, {1.0f, 1.0f, 1.0f}};
    const engine::Material bright{"bright", {0.5f, 0.5f, 0.5f}, {}, {3.0f, 3.0f, 3.0f}};
    const engine::Material plain{"plain", {0.5f, 0.5f, 0.5f}, {}, {}};
    scene.mesh = engine::with_material(engine::make_ground(0.0f, 0.0f, 0.0f, 1.0f), dim);   // area 4, power 4
    scene.mesh.append(engine::with_material(engine::make_ground(1.0f, 0.0f, 0.0f, 0.5f), bright));  // area 1, power 3
    scene.mesh.append(engine::with_material(engine::make_ground(2.0f, 0.0f, 0.0f, 1.0f), plain));
    scene.lights.push_back({{0, 5, 0}, {1, 1, 1}});
    const engine::LightSet lights(scene);
    CHECK(lights.emitter_count() == 4);  // two triangles per quad; the plain quad does not emit
    CHECK(lights.points().size() == 1);
    engine::SampleStream s(1, 1, 1);
    int on_bright = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        const float u0 = s.next(), u1 = s.next(), u2 = s.next();
        const engine::AreaSample a = lights.sample_area(u0, u1, u2);
        REQUIRE((a.point.y == 0.0f || a.point.y == 1.0f));
        REQUIRE(std::fabs(a.normal.y) == doctest::Approx(1.0f));
        if (a.point.y == 1.0f) {
            ++on_bright;
            REQUIRE(a.radiance.x == 3.0f);
            // Each bright triangle (area 0.5) is picked with probability 3/14.
            REQUIRE(a.pdf_area == doctest::Approx((3.0 / 14.0) / 0.5));
        } else {
            REQUIRE(a.pdf_area == doctest::Approx((4.0 / 14.0) / 2.0));
        }
    }
    CHECK(double(on_bright) / n == doctest::Approx(3.0 / 7.0).epsilon(0.03));
}
