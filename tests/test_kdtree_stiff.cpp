// kd-tree stiff cases against brute: axis-parallel rays with +0/-0 components, rays along the
// lines of integer-grid meshes (inside split planes, through leaf edges and corners), origins
// exactly on split planes and on leaf corners, far and tiny scenes.
#include "accel/factory/make_accel.h"
#include "accel/kdtree/kdtree_build.h"
#include "accel/kdtree/kdtree_walk_dir.h"
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

/// The six axis directions with every sign combination of the two zero components.
std::vector<Vec3f> axis_directions() {
    std::vector<Vec3f> dirs;
    for (int k = 0; k < 3; ++k)
        for (const float s : {1.0f, -1.0f})
            for (int z = 0; z < 4; ++z) {
                Vec3f d{0.0f, 0.0f, 0.0f};
                d[(k + 1) % 3] = (z & 1) ? -0.0f : 0.0f;
                d[(k + 2) % 3] = (z & 2) ? -0.0f : 0.0f;
                d[k] = s;
                dirs.push_back(d);
            }
    return dirs;
}

}  // namespace

TEST_CASE("kdtree stiff: integer grid mesh, rays along and through the grid lines") {
    const engine::Mesh grid = testing::integer_grid(6);
    std::vector<Ray> rays;
    const auto dirs = axis_directions();
    for (int j = -1; j <= 7; ++j)
        for (int i = -1; i <= 7; ++i)
            for (const float h : {0.0f, 0.5f}) {
                const float x = float(i) + h, y = float(j);
                for (const Vec3f& d : dirs) {
                    // Perpendicular rays hit at vertices and edges; in-plane rays run along grid lines.
                    const Vec3f o{x - 8.0f * d.x, y - 8.0f * d.y, -8.0f * d.z};
                    rays.push_back({o, 0.0f, d, inf});
                    rays.push_back({{y, x, 0.0f}, 0.0f, d, inf});  // origin on the mesh, on grid lines
                }
                // Diagonal rays through grid vertices: x, y and z planes are crossed at one point.
                rays.push_back({{x - 1.0f, y - 1.0f, 1.0f}, 0.0f, {1.0f, 1.0f, -1.0f}, inf});
                rays.push_back({{x + 2.0f, y - 2.0f, -2.0f}, 0.0f, {-1.0f, 1.0f, 1.0f}, inf});
                rays.push_back({{x - 1.0f, y - 1.0f, 0.0f}, 0.0f, {1.0f, 1.0f, 0.0f}, inf});
            }
    for (const bool perfect : {true, false}) {
        accel::BuildConfig cfg;
        cfg.kd.perfect_splits = perfect;
        CAPTURE(perfect);
        testing::require_agreement(grid, rays, cfg);
    }
}

TEST_CASE("kdtree stiff: integer cubes, rays along cube edges and through cube corners") {
    const engine::Mesh cubes = testing::integer_cubes(4);
    std::vector<Ray> rays;
    const auto dirs = axis_directions();
    for (int a = -1; a <= 5; ++a)
        for (int b = -1; b <= 5; ++b) {
            for (const Vec3f& d : dirs) {
                const int k = d.x != 0.0f ? 0 : (d.y != 0.0f ? 1 : 2);
                Vec3f o;
                o[k] = d[k] > 0 ? -1.0f : 5.0f;
                o[(k + 1) % 3] = float(a);
                o[(k + 2) % 3] = float(b);
                rays.push_back({o, 0.0f, d, inf});
                o[(k + 2) % 3] = float(b) + 0.5f;  // along a face, through edges
                rays.push_back({o, 0.0f, d, inf});
                o[k] = 2.0f;  // starting inside, on a cube face plane
                rays.push_back({o, 0.0f, d, inf});
            }
            rays.push_back({{float(a) - 2.0f, float(b) - 2.0f, -2.0f}, 0.0f, {1.0f, 1.0f, 1.0f}, inf});
            rays.push_back({{float(a) - 2.0f, float(b), -1.0f}, 0.0f, {1.0f, 0.0f, 1.0f}, inf});
            rays.push_back({{float(a) - 2.0f, float(b) + 2.0f, 1.0f}, 0.0f, {1.0f, -1.0f, -0.0f}, inf});
        }
    for (const bool perfect : {true, false}) {
        accel::BuildConfig cfg;
        cfg.kd.perfect_splits = perfect;
        CAPTURE(perfect);
        testing::require_agreement(cubes, rays, cfg);
    }
}

TEST_CASE("kdtree stiff: origins exactly on split planes and on leaf corners, rays inside split planes") {
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.15f, 5);
    mesh.append(testing::random_soup(400, 0.15f, 3));
    const accel::KdTree tree = accel::build_kdtree(mesh.view());
    const auto boxes = testing::kd_node_boxes(tree);
    std::mt19937 rng(99);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<Ray> rays;
    const auto dirs = axis_directions();
    // Every third node of a big tree, every node of a small one (K_T 12: ~3x fewer planes than 4).
    const std::size_t step = tree.nodes.size() > 3000 ? 3 : 1;
    for (std::size_t i = 0; i < tree.nodes.size() && rays.size() < 6000; i += step) {
        const accel::KdNode n = tree.nodes[i];
        const accel::Bounds& b = boxes[i];
        if (n.is_leaf()) {
            // From a corner of the leaf: every plane through the corner is crossed at t = 0.
            const Vec3f corner{(i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.lo.z : b.hi.z};
            rays.push_back({corner, 0.0f, simd::normalize(Vec3f{g(rng), g(rng), g(rng)}), inf});
            rays.push_back({corner, 0.0f, dirs[i % dirs.size()], inf});
            continue;
        }
        const int k = n.axis();
        Vec3f o{b.lo.x + u(rng) * (b.hi.x - b.lo.x), b.lo.y + u(rng) * (b.hi.y - b.lo.y),
                b.lo.z + u(rng) * (b.hi.z - b.lo.z)};
        o[k] = n.split;
        Vec3f d = simd::normalize(Vec3f{g(rng), g(rng), g(rng)});
        rays.push_back({o, 0.0f, d, inf});
        d[k] = (i & 8) ? -0.0f : 0.0f;  // lying in the split plane
        rays.push_back({o, 0.0f, d, inf});
        rays.push_back({o - d * 3.0f, 0.0f, d, inf});
    }
    CHECK(rays.size() > 500);
    testing::require_agreement(mesh, rays);
}

TEST_CASE("kdtree stiff: far from the origin and tiny scenes") {
    for (const auto& placement : {std::pair{1.0e6f, 1.0f}, std::pair{1.0e7f, 10.0f}, std::pair{0.0f, 1e-6f},
                                  std::pair{1e-3f, 1e-6f}}) {
        // Plain variables, not a structured binding: clang 14 cannot capture bindings in lambdas.
        const float offset = placement.first, scale = placement.second;
        CAPTURE(offset);
        CAPTURE(scale);
        engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.2f, 2);
        mesh.append(testing::random_soup(300, 0.2f, 5));
        testing::place(mesh, offset, scale);
        std::vector<Ray> rays = testing::random_rays_into(mesh.bounds, 800, 6);
        const auto inside = testing::random_rays_inside(mesh.bounds, 800, 7);
        rays.insert(rays.end(), inside.begin(), inside.end());
        testing::require_agreement(mesh, rays);
    }
}

TEST_CASE("kdtree stiff: a direction component whose shear underflows is walked as zero (found by a search over extreme rays)") {
    using accel::kd::shears_to_zero;
    using accel::kd::walk_direction;
    // shears_to_zero is the triangle test's own rounding, |d| / dmax == 0 in float, without the
    // division: on both sides of the 2^-150 boundary, at it, and far from it.
    std::mt19937 rng(20261203);
    std::uniform_int_distribution<int> ex(-149, 127);
    std::uniform_real_distribution<float> mant(1.0f, 2.0f);
    std::size_t zeros = 0;
    for (int i = 0; i < 200000; ++i) {
        const float dmax = std::ldexp(mant(rng), ex(rng) / 2 + 63);  // >= 2^-11, normal
        float dk = std::ldexp(mant(rng), ex(rng));
        if (i % 4 == 0) dk = std::nextafter(float(double(dmax) * 0x1p-150), i % 8 == 0 ? 0.0f : INFINITY);
        if (i % 16 == 1) dk = float(double(dmax) * 0x1p-150);
        if (!(std::fabs(dk) <= dmax) || dk == 0.0f) continue;
        for (const float s : {dk, -dk}) {
            CAPTURE(s);
            CAPTURE(dmax);
            const bool ref = std::fabs(s) / dmax == 0.0f;
            CHECK(shears_to_zero(s, dmax) == ref);
            zeros += ref ? 1 : 0;
        }
    }
    CHECK(zeros > 1000);
    // The batch form lane by lane.
    using P = xsimd::batch<float>;
    alignas(64) float d[P::size], m[P::size];
    for (std::size_t l = 0; l < P::size; ++l) d[l] = std::ldexp(1.0f, -150 + int(l) % 3) * 3.0f, m[l] = l % 2 ? 3.0f : 2.0f;
    const std::uint32_t bits = simd::to_bits(shears_to_zero(P::load_aligned(d), P::load_aligned(m)));
    for (std::size_t l = 0; l < P::size; ++l) CHECK(((bits >> l) & 1u) == (shears_to_zero(d[l], m[l]) ? 1u : 0u));
    const Vec3f w = walk_direction({-3e30f, -1.7e-42f, 2e29f});
    CHECK(w.x == -3e30f);
    CHECK(w.y == 0.0f);
    CHECK(std::signbit(w.y));
    CHECK(w.z == 2e29f);

    // Rays lying in the bottom face of a box (origin on it, d.y ~ 1e-42 against d ~ 1e30 along it):
    // the triangle test sees no motion along y and hits the face; every path of the kd-tree agrees.
    engine::Mesh mesh = engine::make_box({-2, -2, -2}, {2, -1.5f, 2});
    mesh.append(engine::make_icosphere({0, 0, 0}, 1.0f, 1, 0.1f, 3));
    mesh.compute_bounds();
    std::vector<Ray> rays;
    std::uniform_real_distribution<float> u(-1.9f, 1.9f);
    for (int i = 0; i < 2000; ++i) {
        const Vec3f o{u(rng), -2.0f, u(rng)};
        const Vec3f dir{u(rng) * std::ldexp(1.0f, 60 + i % 60), -std::ldexp(1.0f, -141 + i % 3), u(rng) * std::ldexp(1.0f, 60 + i % 60)};
        rays.push_back({o, 0.0f, dir, inf});
    }
    testing::require_agreement(mesh, rays);  // scalar vs brute, every SIMD path vs scalar
    const auto kd = accel::make_kdtree_accel(mesh.view(), {});
    const testing::OracleResult r = testing::compare_with_brute(*kd, accel::BruteAccel(mesh.view()), mesh.view(), rays);
    CHECK(r.hits > 1000);  // the face's triangles are hit (the rays do not leave it at t = 0)
}
