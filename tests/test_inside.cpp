// Inside or outside (accel::inside_points): crossing parity with a second direction in the band,
// against the double-precision winding number on every closed shared model and on procedural
// closed meshes, on every structure; points near edges, on the surface and non-finite.
#include "accel/factory/make_accel.h"
#include "accel/interface/inside.h"
#include "engine/procedural.h"
#include "query_check.h"
#include "stress/stress_case.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace arbor;
using accel::Vec3f;

namespace {

#if defined(ARBOR_SANITIZED_BUILD)
constexpr std::size_t points_per_mesh = 40;
#else
constexpr std::size_t points_per_mesh = 300;
#endif

/// Points in the box grown by 10%, at least `gap` (box diagonals) away from the surface, and the
/// winding number's verdict for each (odd: inside).
void random_points(const engine::Mesh& m, std::size_t n, float gap, std::uint32_t seed, std::vector<Vec3f>& points,
                   std::vector<std::uint8_t>& inside) {
    const auto bvh = accel::make_accel(accel::AccelKind::bvh_sah, m.view());
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-0.1f, 1.1f);
    const Vec3f lo = m.bounds.lo, ext = m.bounds.extent();
    const float diag = simd::length(ext);
    while (points.size() < n) {
        const Vec3f p{lo.x + u(rng) * ext.x, lo.y + u(rng) * ext.y, lo.z + u(rng) * ext.z};
        std::vector<accel::PointHit> near(1);
        bvh->closest_points(std::vector<Vec3f>{p}, gap * diag, near);
        if (near[0].is_hit()) continue;  // too close to the surface to call
        const double w = testing::winding_number(m, p);
        REQUIRE(std::fabs(w - std::round(w)) < 1e-6);  // off the surface of a closed mesh: an integer
        points.push_back(p);
        inside.push_back(std::uint8_t(std::llround(w) % 2 != 0));
    }
}

void check_inside(const engine::Mesh& m, const std::vector<Vec3f>& points, const std::vector<std::uint8_t>& expect,
                  bool every_width) {
    for (const auto& s : testing::query_structures(m.view(), every_width)) {
        CAPTURE(s.name);
        std::vector<std::uint8_t> got(points.size(), 7);
        accel::inside_points(*s.accel, m.bounds, points, got);
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < points.size(); ++i) wrong += got[i] != expect[i];
        CHECK(wrong == 0);
    }
}

}  // namespace

TEST_CASE("inside: agrees with the winding number on every closed shared model, on every structure") {
    std::size_t closed = 0, inside = 0, total = 0;
    testing::for_each_shared_mesh([&](const std::string&, const engine::Mesh& mesh) {
        if (!stress::is_closed(mesh)) return;
        ++closed;
        std::vector<Vec3f> points;
        std::vector<std::uint8_t> expect;
        random_points(mesh, points_per_mesh, 1e-4f, 17, points, expect);
        for (auto e : expect) inside += e;
        total += points.size();
        check_inside(mesh, points, expect, false);
    });
    CHECK(closed >= 4);  // cheburashka, cow, rocker-arm, spot
    CHECK(inside * 20 > total);  // the sample holds inside points (> 5%; 16 of 160 in the sanitized build)
}

TEST_CASE("inside: procedural closed meshes at every width, nested surfaces by parity") {
    engine::Mesh m = engine::make_icosphere({0, 0, 0}, 2.0f, 3, 0.15f, 3);
    m.append(engine::make_icosphere({0.2f, 0.1f, 0.0f}, 0.8f, 2));  // a hollow: inside it is outside
    m.append(engine::make_torus({4.5f, 0, 0}, 1.5f, 0.5f, 32, 16));
    m.append(engine::make_box({-1, 3, -1}, {1, 3.5f, 1}));
    m.compute_bounds();
    REQUIRE(stress::is_closed(m));
    std::vector<Vec3f> points;
    std::vector<std::uint8_t> expect;
    random_points(m, points_per_mesh, 1e-4f, 5, points, expect);
    check_inside(m, points, expect, true);
}

TEST_CASE("inside: rays grazing edges take another direction, and points on the surface or non-finite") {
    // Points placed so that the first direction's ray passes within float rounding of an edge of a
    // closed box: the watertight test still counts one face there, and every answer matches the
    // winding number.
    const engine::Mesh box = engine::make_box({-1, -1, -1}, {1, 1, 1});
    const Vec3f d0 = accel::inside_directions()[0];
    std::vector<Vec3f> points;
    std::vector<std::uint8_t> expect;
    for (int i = 0; i < 64; ++i) {
        const float z = -0.9f + 1.8f * float(i) / 63.0f;
        const Vec3f edge = i % 4 == 0 ? Vec3f{1, 1, z} : i % 4 == 1 ? Vec3f{-1, z, 1} : i % 4 == 2 ? Vec3f{z, -1, -1} : Vec3f{1, z, -1};
        for (float s : {0.3f, -0.3f}) {
            const Vec3f p = edge - d0 * s;  // s > 0: the ray from p runs through the edge
            const double w = testing::winding_number(box, p);
            if (std::fabs(w - std::round(w)) > 1e-6) continue;
            points.push_back(p);
            expect.push_back(std::uint8_t(std::llround(w) % 2 != 0));
        }
    }
    REQUIRE(points.size() > 100);
    check_inside(box, points, expect, true);

    // Exactly through an edge: a ray along +z from (x, y, z) with x == y crosses the top face on
    // the diagonal both its triangles share (edge functions of exactly 0): the triangle test's tie
    // rule counts one of them, and the answer is right whether or not the band (a barycentric of
    // 0) sends the point on to the next direction.
    const std::vector<Vec3f> axis_first = {{0, 0, 1}, accel::inside_directions()[1]};
    accel::InsideConfig cfg;
    cfg.directions = axis_first;
    std::vector<Vec3f> diagonal;
    for (int i = 0; i < 20; ++i) diagonal.push_back({-0.9f + 0.09f * float(i), -0.9f + 0.09f * float(i), 0.25f - 0.05f * float(i)});
    for (const auto& s : testing::query_structures(box.view(), true)) {
        CAPTURE(s.name);
        const auto lists = testing::all_hits(*s.accel, {{diagonal[3], 0.0f, axis_first[0], INFINITY}});
        CHECK(lists[0].size() == 1);  // once, not once per triangle
        std::vector<std::uint8_t> got(diagonal.size(), 7);
        accel::inside_points(*s.accel, box.bounds, diagonal, got, cfg);
        for (std::uint8_t g : got) CHECK(g == 1);
    }

    // On the surface (vertices, edges, faces) any answer is right, but it is an answer; outside
    // far away, non-finite: outside.
    const auto bvh = accel::make_accel(accel::AccelKind::bvh_sah, box.view());
    std::vector<Vec3f> odd = {{1, 1, 1}, {1, 0, 0.5f}, {1, 0.2f, 0.3f}, {1e30f, 0, 0}, {NAN, 0, 0}, {0, INFINITY, 0}, {0, 0, 0}};
    std::vector<std::uint8_t> got(odd.size(), 7);
    accel::inside_points(*bvh, box.bounds, odd, got);
    for (int i = 0; i < 3; ++i) CHECK(got[std::size_t(i)] <= 1);
    CHECK(got[3] == 0);
    CHECK(got[4] == 0);
    CHECK(got[5] == 0);
    CHECK(got[6] == 1);
}
