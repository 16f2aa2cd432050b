// Inside by winding number on real models: on every closed shared model it agrees with the
// crossing parity away from the surface; on open meshes made by deleting faces of a closed model
// its verdict keeps the closed original's inside where the parity breaks down.
#include "accel/factory/make_accel.h"
#include "accel/interface/inside.h"
#include "stress/stress_case.h"
#include "testing.h"
#include "winding_check.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace arbor;
using accel::Vec3f;

namespace {

#if defined(ARBOR_SANITIZED_BUILD)
constexpr std::size_t points_per_mesh = 200;
#else
constexpr std::size_t points_per_mesh = 3000;
#endif

/// Uniform points in the mesh's box grown by 10% whose closest surface point is farther than
/// `gap` box diagonals.
std::vector<Vec3f> points_off_surface(const engine::Mesh& m, std::size_t n, double gap, std::uint32_t seed) {
    const auto bvh = accel::make_accel(accel::AccelKind::bvh_sah, m.view());
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-0.1f, 1.1f);
    const Vec3f lo = m.bounds.lo, ext = m.bounds.extent();
    const float reach = float(gap * simd::length(ext));
    std::vector<Vec3f> out;
    std::vector<accel::PointHit> near(1);
    while (out.size() < n) {
        const Vec3f p{lo.x + u(rng) * ext.x, lo.y + u(rng) * ext.y, lo.z + u(rng) * ext.z};
        bvh->closest_points(std::vector<Vec3f>{p}, reach, near);
        if (!near[0].is_hit()) out.push_back(p);
    }
    return out;
}

std::vector<std::uint8_t> by_parity(const engine::Mesh& m, const std::vector<Vec3f>& points) {
    const auto bvh = accel::make_accel(accel::AccelKind::bvh_sah, m.view());
    std::vector<std::uint8_t> out(points.size());
    accel::inside_points(*bvh, m.bounds, points, out);
    return out;
}

std::vector<std::uint8_t> by_winding(const engine::Mesh& m, const std::vector<Vec3f>& points) {
    const auto bvh = accel::make_accel(accel::AccelKind::bvh_sah, m.view());
    std::vector<double> w(points.size());
    bvh->make_winding_tree(m.view())->winding_numbers(points, accel::default_winding_beta, w);
    std::vector<std::uint8_t> out(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) out[i] = w[i] >= 0.5;
    return out;
}

}  // namespace

TEST_CASE("winding: agrees with the parity on every closed shared model off the surface") {
    // Points not within 1e-5 diagonals of the surface; fast winding numbers (beta 2) on bvh-sah.
    std::size_t closed = 0, inside = 0, total = 0;
    testing::for_each_shared_mesh([&](const std::string&, const engine::Mesh& mesh) {
        if (!stress::is_closed(mesh)) return;
        ++closed;
        const auto points = points_off_surface(mesh, points_per_mesh, 1e-5, 21);
        const auto parity = by_parity(mesh, points), winding = by_winding(mesh, points);
        std::size_t differ = 0;
        for (std::size_t i = 0; i < points.size(); ++i) differ += parity[i] != winding[i], inside += parity[i];
        total += points.size();
        CHECK(differ == 0);
    });
    CHECK(closed >= 4);
    CHECK(inside * 20 > total);  // the sample holds inside points
}

TEST_CASE("winding: open meshes from a closed model keep its inside (1%, 5%, 20% of faces deleted)") {
    // Truth: the closed original's inside (parity; it agrees with the winding number there).
    // Points farther than 1% of the diagonal from the original surface. The winding verdict must
    // match on >= 99%; the parity's share is printed (it counts crossings of whatever surface is
    // left, so a ray through a hole flips it).
    testing::for_each_shared_mesh([&](const std::string& path, const engine::Mesh& mesh) {
        if (path.find("spot") == std::string::npos && path.find("rocker-arm") == std::string::npos) return;
        REQUIRE(stress::is_closed(mesh));
        const auto points = points_off_surface(mesh, points_per_mesh, 0.01, 22);
        const auto truth = by_parity(mesh, points);
        for (unsigned permille : {10u, 50u, 200u}) {
            CAPTURE(permille);
            const engine::Mesh open = testing::without_faces(mesh, permille, 5);
            REQUIRE(open.triangle_count() < mesh.triangle_count());
            const auto winding = by_winding(open, points), parity = by_parity(open, points);
            std::size_t w_ok = 0, p_ok = 0;
            for (std::size_t i = 0; i < points.size(); ++i)
                w_ok += winding[i] == truth[i], p_ok += parity[i] == truth[i];
            const double w_share = double(w_ok) / double(points.size()), p_share = double(p_ok) / double(points.size());
            MESSAGE(path << ", " << permille / 10.0 << "% of faces deleted: winding right on " << 100.0 * w_share
                         << "%, parity on " << 100.0 * p_share << "%");
            CHECK(w_share >= 0.99);
        }
    });
}
