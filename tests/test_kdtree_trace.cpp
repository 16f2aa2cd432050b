// kd-tree traversal against the brute oracle: procedural meshes and every shared model with
// coherent, incoherent and random rays, closest and any hit; watertightness; untraceable rays.
#include "accel/factory/make_accel.h"
#include "accel/interface/trace.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"
#include "kdtree_checks.h"
#include "kdtree_oracle.h"

#include <tbb/global_control.h>

#include <filesystem>

using namespace arbor;
using accel::Hit;
using accel::Ray;
using accel::Vec3f;
using accel::BuildConfig;

namespace {

std::vector<Ray> mixed_rays(const accel::Bounds& b, std::size_t n, std::uint32_t seed) {
    std::vector<Ray> rays = testing::camera_rays(b, 24, int(n / 24) + 1);
    const auto inside = testing::random_rays_inside(b, n, seed);
    const auto into = testing::random_rays_into(b, n, seed + 1);
    rays.insert(rays.end(), inside.begin(), inside.end());
    rays.insert(rays.end(), into.begin(), into.end());
    return rays;
}

}  // namespace

TEST_CASE("kdtree trace: agrees with brute on procedural meshes (coherent, incoherent, random rays)") {
    const engine::Mesh meshes[] = {
        engine::make_icosphere({0.1f, 0.2f, -0.3f}, 1.0f, 3, 0.1f, 3),
        engine::make_torus({0, 0, 0}, 1.0f, 0.3f, 32, 16),
        testing::random_soup(1500, 0.2f, 9),
        testing::integer_cubes(4),
    };
    for (const bool perfect : {true, false}) {
        BuildConfig cfg;
        cfg.kd.perfect_splits = perfect;
        for (std::size_t i = 0; i < std::size(meshes); ++i) {
            CAPTURE(perfect);
            CAPTURE(i);
            testing::require_agreement(meshes[i], mixed_rays(meshes[i].bounds, 600, std::uint32_t(i)), cfg);
        }
    }
}

TEST_CASE("kdtree trace: agrees with brute on every shared model") {
    const auto paths = testing::model_paths();
    for (const auto& path : paths) {
        CAPTURE(path);
        engine::Warnings w;
        const engine::Mesh mesh = engine::load_obj(path, w);
        // Brute costs rays * triangles; keep that near 4e6 per model (the sanitizer build is slow).
        const std::size_t n = std::clamp<std::size_t>(4000000 / (3 * mesh.triangle_count()), 48, 1000);
        testing::require_agreement(mesh, mixed_rays(mesh.bounds, n, 77));
    }
}

TEST_CASE("kdtree trace: watertight closed mesh through the kd-tree (rays at vertices and edges)") {
    for (int seed = 1; seed <= 2; ++seed) {
        const Vec3f center{1000.0f * float(seed - 1), 3.0f, -7.0f};
        const engine::Mesh mesh = engine::make_icosphere(center, 2.0f, 3, 0.2f, std::uint32_t(seed));
        const auto kd_built = accel::make_kdtree_accel(mesh.view());
        const accel::KdTreeAccel& kd = *kd_built;
        std::vector<Ray> rays;
        const auto v = mesh.view();
        for (const Vec3f& o : {center, center + Vec3f{0.31f, -0.17f, 0.05f}}) {
            for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
                const Vec3f a = v.corner(t, 0), b = v.corner(t, 1), c = v.corner(t, 2);
                for (const Vec3f& target : {a, (a + b) * 0.5f, (b + c) * 0.5f, a * 0.75f + c * 0.25f})
                    rays.push_back({o, 0.0f, target - o, std::numeric_limits<float>::infinity()});
            }
        }
        std::vector<Hit> hits(rays.size()), any(rays.size());
        kd.trace(rays, hits, {accel::Query::closest, accel::TracePath::scalar});
        kd.trace(rays, any, {accel::Query::any, accel::TracePath::scalar});
        std::size_t leaks = 0, any_leaks = 0, off = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            leaks += !hits[i].is_hit();
            any_leaks += !any[i].is_hit();
        }
        for (std::size_t i = 0; i < rays.size() / 2; ++i) off += std::fabs(hits[i].t - 1.0f) > 1e-4f;
        CAPTURE(seed);
        CHECK(leaks == 0);
        CHECK(any_leaks == 0);
        CHECK(off == 0);
    }
}

TEST_CASE("kdtree trace: untraceable rays miss, empty and one-triangle scenes") {
    const engine::Mesh mesh = engine::make_box({-1, -1, -1}, {1, 1, 1});
    const auto kd_built = accel::make_kdtree_accel(mesh.view());
    const accel::KdTreeAccel& kd = *kd_built;
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const std::vector<Ray> rays = {
        {{0, 0, 5}, 0, {0, 0, -1}, inf},  {{nan, 0, 5}, 0, {0, 0, -1}, inf}, {{0, 0, 5}, 0, {0, nan, -1}, inf},
        {{0, 0, 5}, nan, {0, 0, -1}, inf}, {{0, 0, 5}, 0, {0, 0, -1}, nan},  {{inf, 0, 5}, 0, {0, 0, -1}, inf},
        {{0, 0, 5}, 0, {0, 0, -inf}, inf}, {{0, 0, 5}, 0, {0, 0, 0}, inf},   {{0, 0, 5}, 10, {0, 0, -1}, 1},
    };
    std::vector<Hit> hits(rays.size()), any(rays.size());
    kd.trace(rays, hits, {accel::Query::closest, accel::TracePath::scalar});
    kd.trace(rays, any, {accel::Query::any, accel::TracePath::scalar});
    CHECK(hits[0].is_hit());
    CHECK(hits[0].t == doctest::Approx(4.0f));
    for (std::size_t i = 1; i < rays.size(); ++i) {
        CAPTURE(i);
        CHECK_FALSE(hits[i].is_hit());
        CHECK_FALSE(any[i].is_hit());
        CHECK(std::isinf(hits[i].t));
    }
    // No triangles at all (every one non-finite): everything misses.
    engine::Mesh bad = mesh;
    for (float& x : bad.x) x = nan;
    const auto empty_built = accel::make_kdtree_accel(bad.view());
    const accel::KdTreeAccel& empty = *empty_built;
    CHECK(empty.stats().dropped_nonfinite == 12);
    std::vector<Hit> h(1);
    empty.trace(std::span(rays).first(1), h, {accel::Query::closest, accel::TracePath::scalar});
    CHECK_FALSE(h[0].is_hit());
    // One triangle.
    engine::Mesh one;
    one.add_vertex({0, 0, 0}), one.add_vertex({1, 0, 0}), one.add_vertex({0, 1, 0});
    one.add_triangle(0, 1, 2);
    one.compute_bounds();
    testing::require_agreement(one, mixed_rays(one.bounds, 300, 4));
}

TEST_CASE("kdtree trace: tracing in parallel gives the same answers as one thread") {
    const engine::Mesh mesh = engine::make_torus({0, 0, 0}, 1.0f, 0.4f, 48, 24);
    const auto kd_built = accel::make_kdtree_accel(mesh.view());
    const accel::KdTreeAccel& kd = *kd_built;
    const auto rays = testing::random_rays_inside(mesh.bounds, 4000, 8);
    std::vector<Hit> serial(rays.size()), parallel(rays.size());
    kd.trace(rays, serial, {accel::Query::closest, accel::TracePath::scalar});
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
        accel::trace_parallel(kd, rays, parallel, accel::Query::closest, accel::TracePath::best, 64);
    }
    for (std::size_t i = 0; i < rays.size(); ++i) {
        CHECK(serial[i].prim == parallel[i].prim);
        CHECK(serial[i].t == parallel[i].t);
    }
}

TEST_CASE("kdtree trace: the counted walk gives the same answers and plausible counts") {
    const engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 3);
    const auto kd_built = accel::make_kdtree_accel(mesh.view());
    const accel::KdTreeAccel& kd = *kd_built;
    const auto rays = testing::random_rays_into(mesh.bounds, 500, 12);
    for (const bool any : {false, true}) {
        std::vector<Hit> plain(rays.size()), counted(rays.size());
        if (any) kd.trace(rays, plain, {accel::Query::any, accel::TracePath::scalar});
        else kd.trace(rays, plain, {accel::Query::closest, accel::TracePath::scalar});
        accel::TraceCounters c;
        REQUIRE(kd.offer().counts);
        kd.trace(rays, counted, {any ? accel::Query::any : accel::Query::closest, accel::TracePath::scalar, {}, {}, &c});
        for (std::size_t i = 0; i < rays.size(); ++i) {
            CHECK(plain[i].prim == counted[i].prim);
            CHECK(plain[i].t == counted[i].t);
        }
        CAPTURE(any);
        CHECK(c.rays == rays.size());
        CHECK(c.nodes_visited > rays.size());              // every ray descends from the root at least
        CHECK(c.triangles_tested > rays.size() / 2);       // most rays hit, so they test something
        CHECK(c.triangles_tested < 50 * rays.size());      // and the tree culls (1280 triangles)
    }
}
