// kd-tree on degenerate input: the build never breaks (bounded depth and size) and tracing still
// agrees with brute.
#include "accel/kdtree/kdtree_build.h"
#include "engine/procedural.h"
#include "kdtree_checks.h"
#include "kdtree_oracle.h"

#include <random>

using namespace arbor;
using accel::Hit;
using accel::Ray;
using accel::Vec3f;

namespace {

const float inf = std::numeric_limits<float>::infinity();

/// Rays with origins inside `b` (interpolated, so boxes near FLT_MAX do not overflow) and random
/// directions, plus rays from outside aimed at random inside points.
std::vector<Ray> safe_rays(const accel::Bounds& b, std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::normal_distribution<float> g(0.0f, 1.0f);
    const auto lerp = [](float lo, float hi, float t) { return lo * (1.0f - t) + hi * t; };
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3f p{lerp(b.lo.x, b.hi.x, u(rng)), lerp(b.lo.y, b.hi.y, u(rng)), lerp(b.lo.z, b.hi.z, u(rng))};
        const Vec3f d = simd::normalize(Vec3f{g(rng), g(rng), g(rng)});
        rays.push_back({p, 0.0f, d, inf});
        const Vec3f q{lerp(b.lo.x, b.hi.x, u(rng)), lerp(b.lo.y, b.hi.y, u(rng)), lerp(b.lo.z, b.hi.z, u(rng))};
        rays.push_back({p, 0.0f, q * 0.5f - p * 0.5f, inf});  // towards another inside point
    }
    return rays;
}

void check_build(const engine::Mesh& mesh, bool refs_check) {
    const accel::KdTree tree = accel::build_kdtree(mesh.view());
    CHECK(testing::check_kdtree_structure(tree, mesh.view()) == "");
    CHECK(testing::check_kdtree_ropes(tree) == "");
    if (refs_check) CHECK(testing::check_kdtree_refs(tree, mesh.view()) == "");
    CHECK(accel::kd_tree_stats(tree).max_depth <= tree.depth_limit);
}

}  // namespace

TEST_CASE("kdtree degenerate: 100k copies of one triangle") {
    engine::Mesh mesh;
    mesh.add_vertex({0.1f, 0.2f, 0.3f}), mesh.add_vertex({1.1f, 0.4f, 0.2f}), mesh.add_vertex({0.5f, 1.3f, 0.9f});
    for (int i = 0; i < 100000; ++i) mesh.add_triangle(0, 1, 2);
    mesh.compute_bounds();
    const accel::KdTree tree = accel::build_kdtree(mesh.view());
    const auto st = accel::kd_tree_stats(tree);
    CHECK(testing::check_kdtree_structure(tree, mesh.view()) == "");
    // Copies cannot be separated by any plane: a few empty-space cuts at most, never duplication.
    CHECK(st.max_depth <= tree.depth_limit);
    CHECK(st.refs <= 2 * 100000);
    CHECK(st.max_leaf_size == 100000);
    testing::require_agreement(mesh, safe_rays(mesh.bounds, 40, 1));
}

TEST_CASE("kdtree degenerate: all centroids equal (triangles rotated about one point)") {
    engine::Mesh mesh;
    std::mt19937 rng(3);
    std::normal_distribution<float> g(0.0f, 1.0f);
    const Vec3f c{0.25f, -0.5f, 2.0f};
    for (int i = 0; i < 2000; ++i) {
        const Vec3f a{g(rng), g(rng), g(rng)}, b{g(rng), g(rng), g(rng)};
        const auto i0 = mesh.add_vertex(c + a), i1 = mesh.add_vertex(c + b), i2 = mesh.add_vertex(c - a - b);
        mesh.add_triangle(i0, i1, i2);
    }
    mesh.compute_bounds();
    check_build(mesh, false);
    testing::require_agreement(mesh, safe_rays(mesh.bounds, 300, 2));
}

TEST_CASE("kdtree degenerate: all triangles in one plane (axis-aligned and tilted)") {
    // Axis-aligned: the scene box is flat, every triangle lies in the plane z = 0.25.
    engine::Mesh flat = testing::random_soup(600, 0.2f, 8);
    for (float& z : flat.z) z = 0.25f;
    flat.compute_bounds();
    check_build(flat, true);
    std::vector<Ray> rays = safe_rays(flat.bounds, 300, 3);
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(-1.2f, 1.2f);
    for (int i = 0; i < 300; ++i) {
        rays.push_back({{u(rng), u(rng), 1.0f}, 0.0f, {u(rng) * 0.3f, u(rng) * 0.3f, -1.0f}, inf});
        rays.push_back({{u(rng), u(rng), 0.25f}, 0.0f, {u(rng), u(rng), (i & 1) ? 0.0f : -0.0f}, inf});  // in the plane
        rays.push_back({{u(rng), u(rng), 0.25f}, 0.0f, {0.0f, 0.0f, (i & 1) ? 1.0f : -1.0f}, inf});     // from the plane
    }
    testing::require_agreement(flat, rays);
    // Tilted: z from a plane equation (rounded, so only nearly coplanar).
    engine::Mesh tilted = testing::random_soup(600, 0.2f, 9);
    for (std::size_t i = 0; i < tilted.vertex_count(); ++i) tilted.z[i] = 0.3f * tilted.x[i] - 0.7f * tilted.y[i];
    tilted.compute_bounds();
    check_build(tilted, true);
    testing::require_agreement(tilted, safe_rays(tilted.bounds, 500, 5));
}

TEST_CASE("kdtree degenerate: coordinates near +-FLT_MAX") {
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 2, 0.1f, 4);
    mesh.append(testing::random_soup(200, 0.3f, 6));
    for (auto* v : {&mesh.x, &mesh.y, &mesh.z})
        for (float& f : *v) f = std::clamp(f * 3e38f, -3.3e38f, 3.3e38f);
    mesh.compute_bounds();
    CHECK(mesh.bounds.hi.x > 2.9e38f);
    CHECK(mesh.bounds.lo.x < -2.9e38f);
    check_build(mesh, false);
    testing::require_agreement(mesh, safe_rays(mesh.bounds, 400, 7));
}

TEST_CASE("kdtree degenerate: zero-area, collinear and sliver triangles") {
    engine::Mesh mesh = testing::random_soup(300, 0.3f, 10);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 300; ++i) {
        const Vec3f a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)};
        const auto ia = mesh.add_vertex(a), ib = mesh.add_vertex(b);
        switch (i % 4) {
        case 0: mesh.add_triangle(ia, ia, ib); break;                                 // repeated corner
        case 1: mesh.add_triangle(ia, ib, mesh.add_vertex((a + b) * 0.5f)); break;    // collinear
        case 2: mesh.add_triangle(ia, ia, ia); break;                                 // a point
        default: mesh.add_triangle(ia, ib, mesh.add_vertex((a + b) * 0.5f + Vec3f{0, 1e-6f, 0})); break;  // sliver
        }
    }
    mesh.compute_bounds();
    check_build(mesh, true);
    std::vector<Ray> rays = safe_rays(mesh.bounds, 500, 12);
    // Rays aimed at the slivers' corners and midpoints.
    const auto v = mesh.view();
    for (std::size_t t = 300; t < mesh.triangle_count(); ++t) {
        const Vec3f target = v.corner(t, 2);
        rays.push_back({target + Vec3f{0.3f, 0.5f, -0.2f}, 0.0f, Vec3f{-0.3f, -0.5f, 0.2f}, inf});
    }
    testing::require_agreement(mesh, rays);
}
