// bvh-median and bvh-sah against brute: closest and any hit with coherent, incoherent and random
// rays on every shared model and on procedural meshes; watertightness through the BVH; stiff rays.
#include "bvh_check.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"
#include "accel/factory/make_accel.h"

#include <cmath>

using namespace arbor;
using accel::BuildConfig;
using accel::Ray;
using accel::Vec3f;

TEST_CASE("bvh oracle: every shared model, coherent + incoherent + random rays, closest and any hit") {
    const auto paths = testing::model_paths();
    for (const auto& path : paths) {
        engine::Warnings w;
        const engine::Mesh mesh = engine::load_obj(path, w);
        const accel::BruteAccel brute(mesh.view());
        const auto rays = testing::three_kinds(mesh.bounds, testing::oracle_ray_count(mesh.triangle_count()), 17);
        const auto ref = testing::brute_answers(brute, rays);
        for (const auto& k : testing::bvh_kinds()) {
            CAPTURE(path);
            CAPTURE(k.name);
            const auto bvh = accel::make_accel(k.kind, mesh.view());
            CHECK(testing::check_oracle(*bvh, rays, ref) > rays.size() / 8);
        }
    }
}

TEST_CASE("bvh oracle: procedural meshes at several leaf sizes and bin counts") {
    const engine::Mesh mesh = testing::procedural_shapes();
    const accel::BruteAccel brute(mesh.view());
    const auto rays = testing::three_kinds(mesh.bounds, 700, 23);
    const auto ref = testing::brute_answers(brute, rays);
    for (std::uint32_t leaf : {1u, 3u, 8u})
        for (std::uint32_t bins : {2u, 16u, 32u}) {
            BuildConfig cfg;
            cfg.bvh.max_leaf_size = leaf;
            cfg.bvh.sah_bins = bins;
            cfg.bvh.parallel_threshold = 128;
            for (const auto& k : testing::bvh_kinds()) {
                if (k.kind == accel::AccelKind::bvh_median && bins != 16) continue;
                CAPTURE(leaf);
                CAPTURE(bins);
                CAPTURE(k.name);
                CHECK(testing::check_oracle(*accel::make_accel(k.kind, mesh.view(), cfg), rays, ref) > rays.size() / 8);
            }
        }
}

TEST_CASE("bvh oracle: watertight jittered icospheres, rays aimed at vertices and edges never leak") {
    for (int seed = 1; seed <= 3; ++seed) {
        const Vec3f center{1000.0f * float(seed - 2), 3.0f, -7.0f};
        const engine::Mesh mesh = engine::make_icosphere(center, 2.0f, 3, 0.2f, std::uint32_t(seed));
        const auto v = mesh.view();
        std::vector<Ray> rays;
        const Vec3f origins[] = {center, center + Vec3f{0.31f, -0.17f, 0.05f}, center + Vec3f{-0.5f, 0.5f, 0.25f}};
        for (const Vec3f& o : origins)
            for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
                const Vec3f a = v.corner(t, 0), b = v.corner(t, 1), c = v.corner(t, 2);
                for (const Vec3f& target : {a, (a + b) * 0.5f, (b + c) * 0.5f, a * 0.75f + c * 0.25f})
                    rays.push_back({o, 0.0f, target - o, INFINITY});
            }
        for (const auto& k : testing::bvh_kinds())
            for (std::uint32_t leaf : {1u, 4u}) {
                BuildConfig cfg;
                cfg.bvh.max_leaf_size = leaf;
                const auto bvh = accel::make_accel(k.kind, v, cfg);
                std::vector<accel::Hit> hits(rays.size()), any(rays.size());
                bvh->trace(rays, hits, {accel::Query::closest, accel::TracePath::scalar});
                bvh->trace(rays, any, {accel::Query::any, accel::TracePath::scalar});
                std::size_t leaks = 0, any_leaks = 0, off = 0;
                for (std::size_t i = 0; i < rays.size(); ++i) leaks += !hits[i].is_hit(), any_leaks += !any[i].is_hit();
                for (std::size_t i = 0; i < rays.size() / 3; ++i) off += std::fabs(hits[i].t - 1.0f) > 1e-4f;
                CAPTURE(seed);
                CAPTURE(k.name);
                CAPTURE(leaf);
                CHECK(leaks == 0);
                CHECK(any_leaks == 0);
                CHECK(off == 0);
            }
    }
}

TEST_CASE("bvh oracle: axis-parallel rays with +0/-0 components, rays in box faces, far and tiny scenes") {
    const float s0 = 0.0f, n0 = -0.0f;
    for (const auto& placement : {std::pair{0.0f, 1.0f}, std::pair{1e6f, 1.0f}, std::pair{-3e6f, 10.0f},
                                  std::pair{0.0f, 1e-6f}}) {
        // Plain variables, not a structured binding: clang 14 cannot capture bindings in lambdas.
        const float offset = placement.first, scale = placement.second;
        engine::Mesh mesh = engine::make_box({-1, -1, -1}, {1, 1, 1});
        mesh.append(engine::make_box({-1, -1, 1}, {1, 1, 3}));  // shares the face z = 1
        mesh.append(engine::make_icosphere({0, 0, -3}, 1.0f, 2));
        for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
            mesh.x[i] = mesh.x[i] * scale + offset;
            mesh.y[i] = mesh.y[i] * scale + offset;
            mesh.z[i] = mesh.z[i] * scale + offset;
        }
        mesh.compute_bounds();
        const accel::BruteAccel brute(mesh.view());
        std::vector<Ray> rays;
        auto P = [&](float x, float y, float z) { return Vec3f{x * scale + offset, y * scale + offset, z * scale + offset}; };
        // Along each axis, both signs and both zeros in the other components, from grid points that
        // include box faces (+-1), edges, and the shared face plane z = 1.
        const float coords[] = {-1.0f, -0.5f, 0.0f, 0.3f, 1.0f};
        for (float a : coords)
            for (float b : coords)
                for (int axis = 0; axis < 3; ++axis)
                    for (float sign : {1.0f, -1.0f})
                        for (float zero : {s0, n0}) {
                            Vec3f o, d{zero, zero, zero};
                            o[axis] = -8.0f * sign;
                            o[(axis + 1) % 3] = a;
                            o[(axis + 2) % 3] = b;
                            d[axis] = sign * scale;
                            rays.push_back({P(o.x, o.y, o.z), 0.0f, d, INFINITY});
                            // The same line starting inside the geometry, and one stopped short.
                            o[axis] = 0.0f;
                            rays.push_back({P(o.x, o.y, o.z), 0.0f, d, INFINITY});
                            rays.push_back({P(o.x, o.y, o.z), 0.0f, d, 0.5f});
                        }
        const auto random = testing::three_kinds(mesh.bounds, 400, 31);
        rays.insert(rays.end(), random.begin(), random.end());
        const auto ref = testing::brute_answers(brute, rays);
        for (const auto& k : testing::bvh_kinds())
            for (std::uint32_t leaf : {1u, 4u}) {
                BuildConfig cfg;
                cfg.bvh.max_leaf_size = leaf;
                CAPTURE(offset);
                CAPTURE(scale);
                CAPTURE(k.name);
                CHECK(testing::check_oracle(*accel::make_accel(k.kind, mesh.view(), cfg), rays, ref) > rays.size() / 8);
            }
    }
}
