// engine/ray_gen: the four ray kinds keep their promises (primary rays hit the framed sphere,
// shadow rays stop short of the light, diffuse rays leave on the normal's side with a cosine
// distribution, random rays start inside the bounds), exact counts, the same rays for the same seed
// whatever the thread count, and one-line errors for scenes that cannot give the rays asked for.
#include "accel/structures/brute_accel.h"
#include "engine/error.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"
#include "engine/ray_gen.h"
#include "testing.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstring>
#include <set>

using namespace arbor;
using engine::RayKind;

namespace {

engine::Scene box_scene() {
    return engine::scene_from_mesh(engine::make_box({-1, -1, -1}, {1, 1, 1}), "box");
}

std::vector<accel::Ray> gen(const engine::Scene& s, RayKind kind, std::size_t count, std::uint64_t seed = 1,
                            engine::PixelOrder order = engine::PixelOrder::tiles, engine::ShadowRecipe shadow = {}) {
    const auto g = engine::ray_gen_scene(s);
    accel::BruteAccel brute(g.tris);
    engine::RayGenConfig cfg;
    cfg.kind = kind;
    cfg.count = count;
    cfg.seed = seed;
    cfg.order = order;
    cfg.shadow = shadow;
    return engine::generate_rays(g, cfg, &brute);
}

bool same_bytes(const std::vector<accel::Ray>& a, const std::vector<accel::Ray>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(accel::Ray)) == 0;
}

/// Whether the ray (t >= 0) meets the solid sphere.
bool hits_sphere(const accel::Ray& r, const engine::Sphere& s) {
    const accel::Vec3f oc = r.org - s.center;
    const double a = simd::dot(r.dir, r.dir), b = simd::dot(oc, r.dir), c = double(simd::dot(oc, oc)) - double(s.radius) * s.radius;
    return b * b - a * c >= 0.0 && (b <= 0.0 || c <= 0.0);
}

}  // namespace

TEST_CASE("ray_gen: primary rays all hit the bounding sphere of the framed scene, exact counts") {
    std::vector<engine::Scene> scenes;
    scenes.push_back(box_scene());
    scenes.push_back(engine::scene_from_mesh(engine::make_ground(0.0f, 3.0f, -2.0f, 5.0f), "ground"));
    for (const auto& path : testing::model_paths()) {
        engine::Warnings w;
        scenes.push_back(engine::scene_from_mesh(engine::load_obj(path, w), path));
        break;  // one real model is enough here
    }
    for (const auto& s : scenes) {
        const engine::Sphere sphere = engine::bounding_sphere(s.mesh.bounds);
        for (std::size_t count : {1u, 7u, 1000u, 12345u}) {
            const auto rays = gen(s, RayKind::primary, count);
            REQUIRE(rays.size() == count);
            std::size_t missed = 0;
            for (const auto& r : rays) missed += !hits_sphere(r, sphere);
            CHECK_MESSAGE(missed == 0, s.name, " count ", count);
        }
    }
}

TEST_CASE("ray_gen: tile order is a permutation of row order, and tiles are 8x8 blocks") {
    const auto s = box_scene();
    const auto tiles = gen(s, RayKind::primary, 5000, 3, engine::PixelOrder::tiles);
    const auto rows = gen(s, RayKind::primary, 5000, 3, engine::PixelOrder::rows);
    REQUIRE(tiles.size() == rows.size());
    auto key = [](const accel::Ray& r) { return std::tuple(r.dir.x, r.dir.y, r.dir.z); };
    std::multiset<std::tuple<float, float, float>> a, b;
    for (const auto& r : tiles) a.insert(key(r));
    for (const auto& r : rows) b.insert(key(r));
    CHECK(a == b);
    CHECK_FALSE(same_bytes(tiles, rows));
    // The first 8 rays of tile order are the first 8 of row order (row 0 of tile 0).
    for (int i = 0; i < 8; ++i) CHECK(key(tiles[std::size_t(i)]) == key(rows[std::size_t(i)]));
}

TEST_CASE("ray_gen: shadow rays leave the surface towards the light and end before it") {
    const auto s = box_scene();
    const auto g = engine::ray_gen_scene(s);
    const auto rays = gen(s, RayKind::shadow, 3000);
    REQUIRE(rays.size() == 3000);
    for (const auto& r : rays) {
        REQUIRE(r.tfar < 1.0f);
        REQUIRE(r.tnear == 0.0f);
        // d = light - o, so o + 1*d is the light: the segment [0, tfar] ends short of it.
        const accel::Vec3f end = r.org + r.dir;
        CHECK(simd::length(end - g.light) <= 1e-4f * simd::length(g.light) + 1e-5f);
        // The origin sits on (just outside) the box.
        const float m = std::max(std::fabs(r.org.x), std::max(std::fabs(r.org.y), std::fabs(r.org.z)));
        CHECK(m == doctest::Approx(1.0f).epsilon(1e-4));
        CHECK(m >= 1.0f);
    }
    // Seen from inside a closed box the light is blocked; from outside nothing blocks it here
    // (convex box), so no shadow ray is occluded.
    accel::BruteAccel brute(g.tris);
    std::size_t blocked = 0;
    for (const auto& r : rays) blocked += brute.trace_one(r, accel::Query::any).is_hit();
    CHECK(blocked == 0);
}

TEST_CASE("ray_gen: shadow recipes: an area light's points, a light moved among the geometry, rays through the model") {
    const auto s = box_scene();
    const auto g = engine::ray_gen_scene(s);
    const engine::Sphere sphere = engine::bounding_sphere(g.bounds);
    accel::BruteAccel brute(g.tris);
    auto blocked = [&](const std::vector<accel::Ray>& rays) {
        std::size_t n = 0;
        for (const auto& r : rays) n += brute.trace_one(r, accel::Query::any).is_hit();
        return n;
    };
    const auto point = gen(s, RayKind::shadow, 2000);
    CHECK(same_bytes(point, gen(s, RayKind::shadow, 2000, 1, engine::PixelOrder::tiles, engine::ShadowRecipe{})));

    SUBCASE("area light: every ray ends on the square, at many points, half the box's side wide") {
        engine::ShadowRecipe area;
        area.light_size = 0.5f;  // the box is 2 wide: a square of side 1 around the light
        const auto rays = gen(s, RayKind::shadow, 2000, 1, engine::PixelOrder::tiles, area);
        REQUIRE(rays.size() == 2000);
        const accel::Vec3f facing = simd::normalize(sphere.center - g.light);
        std::set<std::tuple<float, float, float>> ends;
        float widest = 0.0f;
        for (const auto& r : rays) {
            const accel::Vec3f end = r.org + r.dir;
            ends.insert({end.x, end.y, end.z});
            // On the square's plane (through the light, facing the centre), within half a side of the light.
            CHECK(std::fabs(simd::dot(end - g.light, facing)) <= 1e-4f * simd::length(g.light));
            const float off = simd::length(end - g.light);
            CHECK(off <= 0.5f * std::sqrt(2.0f) + 1e-4f);
            widest = std::max(widest, off);
        }
        CHECK(ends.size() > 1900);
        CHECK(widest > 0.6f);
        CHECK(blocked(rays) == 0);  // a convex box blocks no lit point's ray
    }
    SUBCASE("light moved to 0.5 bounding radii, inside the box: no face is lit; from every point, rays inside") {
        engine::ShadowRecipe near;
        near.light_distance = 0.5f;
        CHECK_THROWS_AS(gen(s, RayKind::shadow, 100, 1, engine::PixelOrder::tiles, near), engine::InputError);
        near.from_all = true;
        const auto rays = gen(s, RayKind::shadow, 2000, 1, engine::PixelOrder::tiles, near);
        REQUIRE(rays.size() == 2000);
        const accel::Vec3f light = rays[0].org + rays[0].dir;
        CHECK(simd::length(light - sphere.center) == doctest::Approx(0.5f * sphere.radius).epsilon(1e-4));
        CHECK(simd::dot(light - sphere.center, g.light - sphere.center) > 0.0f);  // towards where it was
        for (const auto& r : rays) {
            const float m = std::max(std::fabs(r.org.x), std::max(std::fabs(r.org.y), std::fabs(r.org.z)));
            CHECK(m < 1.0f);  // on the inner side of its face
        }
        CHECK(blocked(rays) == 0);
    }
    SUBCASE("from every point: the points facing away shoot through the box and are blocked") {
        engine::ShadowRecipe all;
        all.from_all = true;
        const auto rays = gen(s, RayKind::shadow, 2000, 1, engine::PixelOrder::tiles, all);
        REQUIRE(rays.size() == 2000);
        const std::size_t n = blocked(rays);
        CHECK(n > 0);
        CHECK(n < rays.size());
        // A point facing away starts just inside the box (the far side of its face) and is blocked;
        // a point facing the light starts just outside and is not.
        for (const auto& r : rays) {
            const float m = std::max(std::fabs(r.org.x), std::max(std::fabs(r.org.y), std::fabs(r.org.z)));
            CHECK(m == doctest::Approx(1.0f).epsilon(1e-4));
            CHECK(brute.trace_one(r, accel::Query::any).is_hit() == (m < 1.0f));
        }
    }
}

TEST_CASE("ray_gen: diffuse rays lie in the upper hemisphere of the normal, cosine-distributed") {
    // A ground quad seen from above: every normal is +y.
    const auto ground = engine::scene_from_mesh(engine::make_ground(0.0f, 0.0f, 0.0f, 4.0f), "ground");
    const auto rays = gen(ground, RayKind::diffuse, 20000, 5);
    REQUIRE(rays.size() == 20000);
    double mean_cos = 0.0;
    for (const auto& r : rays) {
        REQUIRE(r.dir.y > 0.0f);
        REQUIRE(r.org.y > 0.0f);
        REQUIRE(simd::length(r.dir) == doctest::Approx(1.0f).epsilon(1e-5));
        mean_cos += r.dir.y;
    }
    CHECK(mean_cos / 20000.0 == doctest::Approx(2.0 / 3.0).epsilon(0.015));  // E[cos] = 2/3

    // A box seen from the front-right-above: the normal is the axis of the face the origin is on.
    for (const auto& r : gen(box_scene(), RayKind::diffuse, 5000, 6)) {
        const int axis = simd::max_axis({std::fabs(r.org.x), std::fabs(r.org.y), std::fabs(r.org.z)});
        CHECK(r.dir[axis] * r.org[axis] > 0.0f);
    }
}

TEST_CASE("ray_gen: random rays start inside the bounds with unit directions spread evenly") {
    const auto s = box_scene();
    const auto rays = gen(s, RayKind::random, 20000, 9);
    REQUIRE(rays.size() == 20000);
    accel::Vec3f sum{0.0f};
    for (const auto& r : rays) {
        REQUIRE(s.mesh.bounds.contains({r.org, r.org}));
        REQUIRE(simd::length(r.dir) == doctest::Approx(1.0f).epsilon(1e-5));
        sum += r.dir;
    }
    CHECK(simd::length(sum) / 20000.0f < 0.03f);
}

TEST_CASE("ray_gen: same seed same rays at 1 and 2 threads, another seed other rays") {
    const auto s = box_scene();
    for (RayKind k : {RayKind::primary, RayKind::shadow, RayKind::diffuse, RayKind::random}) {
        std::vector<accel::Ray> one, two;
        {
            tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
            one = gen(s, k, 4000, 42);
        }
        {
            tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
            two = gen(s, k, 4000, 42);
        }
        CHECK_MESSAGE(same_bytes(one, two), engine::to_string(k));
        CHECK_MESSAGE(!same_bytes(one, gen(s, k, 4000, 43)), engine::to_string(k));
    }
}

TEST_CASE("ray_gen: errors") {
    const auto ground = engine::scene_from_mesh(engine::make_ground(0.0f, 0.0f, 0.0f, 4.0f), "ground");
    auto g = engine::ray_gen_scene(ground);
    engine::RayGenConfig cfg;
    cfg.kind = RayKind::shadow;
    cfg.count = 100;
    CHECK_THROWS_AS(engine::generate_rays(g, cfg, nullptr), std::invalid_argument);
    // The light under the ground: the camera sees only the top, so no hit point faces the light.
    g.light = {0.0f, -10.0f, 0.0f};
    accel::BruteAccel brute(g.tris);
    CHECK_THROWS_AS(engine::generate_rays(g, cfg, &brute), engine::InputError);
    CHECK(engine::parse_ray_kind("diffuse") == RayKind::diffuse);
    CHECK_FALSE(engine::parse_ray_kind("ambient"));
}
