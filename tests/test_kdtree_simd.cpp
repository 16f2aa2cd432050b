// The kd-tree's SIMD paths (single, packet, best) against its scalar path (bitwise equal answers)
// and brute (the rayfile.md rule): every shared model with primary, shadow, diffuse and random rays
// (engine/ray_gen.h); the triangle blocks; ties between coplanar duplicates; NaN/Inf/zero and
// inactive lanes, partial packets, packets whose lanes part and meet again; the same answers
// with 1 and 2 threads; what `best` picks. (The stiff and degenerate kd-tree cases run the SIMD
// paths too: kdtree_oracle.h's require_agreement.)
#include "accel/factory/make_accel.h"
#include "accel/kdtree/kdtree_blocks.h"
#include "accel/interface/trace.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"
#include "ray_kinds.h"
#include "kd_simd_check.h"
#include "kdtree_checks.h"
#include "wide_check.h"

#include <tbb/global_control.h>

#include <cmath>

using namespace arbor;
using accel::Hit;
using accel::Ray;
using accel::Vec3f;

namespace {

#if defined(ARBOR_SANITIZED_BUILD)
constexpr std::size_t rays_per_kind = 96;
#else
constexpr std::size_t rays_per_kind = 1024;
#endif

/// SIMD paths vs scalar (bitwise) and vs brute (on `brute_rays` of the rays) on `mesh`.
void check_mesh(const engine::Mesh& mesh, const std::vector<Ray>& rays, std::size_t brute_rays,
                std::vector<std::size_t> chunks = {1024}, accel::BuildConfig cfg = {}) {
    const auto kd_built = accel::make_kdtree_accel(mesh.view(), cfg);
    const accel::KdTreeAccel& kd = *kd_built;
    CHECK(testing::check_kd_simd(kd, rays, chunks) > 0);
    const accel::BruteAccel brute(mesh.view());
    const auto sample = testing::spread(rays.size(), brute_rays);
    std::vector<Ray> sub;
    for (std::size_t i : sample) sub.push_back(rays[i]);
    const auto ref = testing::brute_answers(brute, sub);
    CHECK(testing::check_paths(kd, mesh.view(), rays, sample, ref, chunks.front()) == 3);
}

}  // namespace

TEST_CASE("kdtree simd: every shared model, primary/shadow/diffuse/random rays (three shadow recipes), all paths") {
    for (const auto& path : testing::model_paths()) {
        CAPTURE(path);
        engine::Warnings w;
        const engine::Mesh mesh = engine::load_obj(path, w);
        const auto tracer = accel::make_accel(accel::AccelKind::bvh_sah, mesh.view());
        const std::size_t n = mesh.triangle_count() > 30000 ? rays_per_kind / 2 : rays_per_kind;
        const auto rays = testing::ray_kinds(mesh, n, *tracer, 11);
        check_mesh(mesh, rays, testing::oracle_ray_count(mesh.triangle_count(), 32, 1024));
    }
}

TEST_CASE("kdtree simd: the blocks hold each leaf's triangles in order, NaN-padded") {
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 2, 0.1f, 3);
    mesh.append(engine::make_torus({1.5f, 0.2f, -0.3f}, 1.0f, 0.25f, 24, 8));
    const auto kd_built = accel::make_kdtree_accel(mesh.view());
    const accel::KdTreeAccel& kd = *kd_built;
    const accel::KdTree& tree = kd.tree();
    const auto check = [&tree](const auto& blocks, std::size_t n) {
        REQUIRE(blocks.first.size() == tree.leaves.size() + 1);
        CHECK(blocks.first.front() == 0);
        CHECK(blocks.first.back() == blocks.blocks.size());
        std::size_t bad = 0;
        for (std::size_t l = 0; l < tree.leaves.size(); ++l) {
            const accel::KdLeaf& leaf = tree.leaves[l];
            CHECK(blocks.first[l + 1] - blocks.first[l] == (leaf.count + n - 1) / n);
            for (std::size_t i = 0; i < (blocks.first[l + 1] - blocks.first[l]) * n; ++i) {
                const auto& b = blocks.blocks[blocks.first[l] + i / n];
                const std::size_t s = i % n;
                if (i < leaf.count) {
                    const accel::KdTriangle& t = tree.tris[tree.refs[leaf.first + i]];
                    bad += b.ids[s] != t.prim || b.tris.v[0][0][s] != t.v0.x || b.tris.v[1][1][s] != t.v1.y ||
                           b.tris.v[2][2][s] != t.v2.z;
                } else {
                    bad += b.ids[s] != accel::invalid_prim || !std::isnan(b.tris.v[0][0][s]) || !std::isnan(b.tris.v[2][2][s]);
                }
            }
        }
        CHECK(bad == 0);
    };
    check(accel::make_kd_blocks<8>(tree), 8);
    check(accel::make_kd_blocks<16>(tree), 16);
    const accel::KdTree empty;
    const auto none = accel::make_kd_blocks<8>(empty);
    CHECK(none.blocks.empty());
    CHECK(none.first.size() == 1);
}

TEST_CASE("kdtree simd: coplanar duplicates (equal t, the lowest prim wins) and overlapping leaves") {
    // Stacked copies of one quad grid: every hit is a tie between several prims, in several leaves.
    engine::Mesh mesh;
    for (int copy = 0; copy < 3; ++copy) mesh.append(testing::integer_grid(5));
    mesh.append(engine::make_icosphere({2.5f, 2.5f, 0.0f}, 1.5f, 2));
    mesh.append(engine::make_icosphere({2.5f, 2.5f, 0.0f}, 1.5f, 2));  // the same sphere again
    mesh.compute_bounds();
    auto rays = testing::camera_rays(mesh.bounds, 32, 32);
    const auto inside = testing::random_rays_inside(mesh.bounds, 400, 5);
    const auto into = testing::random_rays_into(mesh.bounds, 400, 6);
    rays.insert(rays.end(), inside.begin(), inside.end());
    rays.insert(rays.end(), into.begin(), into.end());
    for (const bool perfect : {true, false}) {
        accel::BuildConfig cfg;
        cfg.kd.perfect_splits = perfect;
        CAPTURE(perfect);
        check_mesh(mesh, rays, rays.size(), {1024, 13}, cfg);
    }
}

TEST_CASE("kdtree simd: axis-parallel rays with +-0 components on grids, in split planes, from leaf corners") {
    const engine::Mesh cubes = testing::integer_cubes(4);
    std::vector<Ray> rays;
    for (int i = -1; i <= 9; ++i)
        for (int j = -1; j <= 9; ++j) {
            const float a = float(i) * 0.5f, b = float(j) * 0.5f;
            for (const float zero : {0.0f, -0.0f})
                for (const float s : {1.0f, -1.0f}) {
                    rays.push_back({{a, b, -3.0f * s + 2.0f}, 0.0f, {zero, zero, s}, INFINITY});
                    rays.push_back({{-3.0f * s + 2.0f, a, b}, 0.0f, {s, zero, -zero}, INFINITY});
                    rays.push_back({{a, 2.0f, b}, 0.0f, {zero, s, zero}, INFINITY});   // origin on a split plane
                    rays.push_back({{a, b, 2.0f}, 0.0f, {s, s, zero}, INFINITY});      // diagonal in the plane z = 2
                    rays.push_back({{a, b, 1.0f}, 0.0f, {s, 0.5f * s, 0.25f}, INFINITY});  // through edges
                }
        }
    // Packets whose lanes part at different faces: a fan of rays from one corner.
    for (int i = 0; i < 64; ++i) {
        const float u = float(i % 8) / 7.0f, v = float(i / 8) / 7.0f;
        rays.push_back({{0.0f, 0.0f, 0.0f}, 0.0f, {1.0f, u, v}, INFINITY});
        rays.push_back({{4.0f, 4.0f, 4.0f}, 0.0f, {-u, -1.0f, -v}, INFINITY});
    }
    check_mesh(cubes, rays, rays.size(), {1024, 7, 1});
}

TEST_CASE("kdtree simd: NaN, Inf, zero and inactive rays miss, partial and mixed-sign packets") {
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 2);
    mesh.append(engine::make_box({-3, -3, -3}, {-2, -2, -2}));
    const float nan = NAN, inf = INFINITY;
    const std::vector<Ray> bad{{{nan, 0, 0}, 0, {1, 0, 0}, inf},  {{0, 0, -5}, 0, {0, nan, 1}, inf}, {{inf, 0, 0}, 0, {-1, 0, 0}, inf},
                               {{0, 0, -5}, 0, {0, 0, inf}, inf}, {{0, 0, -5}, 0, {0, 0, 0}, inf},   {{0, 0, -5}, 0, {-0.0f, 0, -0.0f}, inf},
                               {{0, 0, -5}, nan, {0, 0, 1}, inf}, {{0, 0, -5}, 0, {0, 0, 1}, nan},   {{0, 0, -5}, 3, {0, 0, 1}, 2},
                               {{0, 0, -5}, inf, {0, 0, 1}, inf}, {{0, 0, -5}, 0, {1e-39f, 0, -1e-40f}, inf}};
    std::vector<Ray> rays;
    for (int i = 0; i < 300; ++i) {
        const float s = (i % 2) ? 1.0f : -1.0f, x = float(i % 17) * 0.1f - 0.8f, y = float(i % 13) * 0.12f - 0.7f;
        rays.push_back({{x, y, -5.0f * s}, 0.0f, {0.01f * float(i % 5) * s, -0.02f * s, s}, INFINITY});
        if (i % 7 == 0) rays.push_back(bad[std::size_t(i / 7) % bad.size()]);
        if (i % 11 == 0) rays.push_back({{-5.0f * s, x, y}, 0.0f, {s, 0.0f, -0.0f}, INFINITY});
        if (i % 5 == 0) rays.push_back({{x, y, -5.0f}, 4.0f, {0.0f, 0.0f, 1.0f}, 4.5f});  // a short interval
    }
    const auto kd_built = accel::make_kdtree_accel(mesh.view());
    const accel::KdTreeAccel& kd = *kd_built;
    for (const auto& cfg : testing::kd_simd_configs()) {
        const auto paths = accel::make_kdtree_accel(kd.tree(), cfg);
        for (const auto path : {accel::TracePath::single, accel::TracePath::packet})
            for (const bool any_hit : {false, true}) {
                const auto hits = testing::kd_simd_trace(*paths, bad, path, any_hit, 16);
                for (const Hit& h : hits) CHECK(!h.is_hit());
            }
    }
    check_mesh(mesh, rays, rays.size(), {1, 3, 16, 17, 64, 1024});
    // An empty scene: every path misses.
    const engine::Mesh empty;
    const auto none_built = accel::make_kdtree_accel(empty.view());
    const accel::KdTreeAccel& none = *none_built;
    for (const auto path : {accel::TracePath::single, accel::TracePath::packet, accel::TracePath::best}) {
        std::vector<Hit> hits(rays.size());
        none.trace(rays, hits, {accel::Query::closest, path});
        for (const Hit& h : hits) CHECK(!h.is_hit());
    }
}

TEST_CASE("kdtree simd: identical answers with 1 and 2 threads") {
    const engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.2f, 4);
    auto rays = testing::random_rays_into(mesh.bounds, 2000, 8);
    const auto cam = testing::camera_rays(mesh.bounds, 48, 48);
    rays.insert(rays.end(), cam.begin(), cam.end());
    const auto kd_built = accel::make_kdtree_accel(mesh.view());
    const accel::KdTreeAccel& kd = *kd_built;
    for (const auto path : {accel::TracePath::single, accel::TracePath::packet, accel::TracePath::best})
        for (const auto q : {accel::Query::closest, accel::Query::any}) {
            std::vector<Hit> one(rays.size()), two(rays.size());
            {
                tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
                accel::trace_parallel(kd, rays, one, q, path, 64);
            }
            {
                tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
                accel::trace_parallel(kd, rays, two, q, path, 64);
            }
            CHECK(std::memcmp(one.data(), two.data(), one.size() * sizeof(Hit)) == 0);
        }
}

TEST_CASE("kdtree simd: best takes the packet walk for camera rays and single rays for scattered ones") {
    const engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 3);
    const auto kd_built = accel::make_kdtree_accel(mesh.view());
    const accel::KdTreeAccel& kd = *kd_built;
    CHECK(kd.offer().has(accel::TracePath::single));
    CHECK(kd.offer().has(accel::TracePath::packet));
    CHECK(kd.offer().packets_pay);
    const auto camera = testing::camera_rays(mesh.bounds, 64, 16);
    const accel::PathChoice c = accel::choose_path(kd.offer(), camera, {});
    CHECK(c.path == accel::TracePath::packet);
    CHECK(!accel::path_reason(c).empty());
    CHECK(accel::choose_path(kd.offer(), testing::random_rays_inside(mesh.bounds, 1024, 3), {accel::Query::any}).path ==
          accel::TracePath::single);
    CHECK(accel::choose_path(kd.offer(), camera, {accel::Query::closest, accel::TracePath::best, accel::RayHint::coherent}).path ==
          accel::TracePath::packet);
    CHECK(accel::choose_path(kd.offer(), camera, {accel::Query::closest, accel::TracePath::best, accel::RayHint::incoherent}).path ==
          accel::TracePath::single);
}
