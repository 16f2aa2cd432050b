// The public C++ API (<arbor/arbor.h>, libarbor.so) as a program uses it: meshes from strided
// arrays with geometry ids, files, every structure name, the four queries against the engine's
// brute force, intersect_all's rows and counts, errors, and batches from several threads at once.
#include "accel/structures/brute_accel.h"
#include "accel/interface/inside.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"
#include "api_shapes.h"
#include "query_check.h"

#include <arbor/arbor.h>

#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <thread>

using accel_ray = arbor::accel::Ray;

namespace {

using arbor::testing::to_public;
using arbor::testing::TwoMeshes;

/// A vertex as a program might hold it: the position among other fields.
struct Vertex {
    float normal[3];
    float pos[3];
    std::uint32_t colour;
};

/// Adds `m` to `scene` through a strided array of Vertex records.
std::uint32_t add_strided(arbor::Scene& scene, const arbor::engine::Mesh& m) {
    std::vector<Vertex> v(m.vertex_count());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = {{0, 1, 0}, {m.x[i], m.y[i], m.z[i]}, 0xFFu};
    return scene.add_mesh(v[0].pos, v.size(), sizeof(Vertex), m.indices.data(), m.triangle_count());
}

bool same(const arbor::Hit& a, const arbor::Hit& b) {
    return std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) && a.geom == b.geom && a.prim == b.prim &&
           std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
           std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v);
}

}  // namespace

TEST_CASE("api: meshes from strided arrays, geometry ids, and every query against brute force, for every structure") {
    using namespace arbor;
    const TwoMeshes m;
    Scene scene;
    CHECK(add_strided(scene, m.sphere) == 0);
    CHECK(add_strided(scene, m.torus) == 1);
    CHECK(scene.meshes() == 2);
    CHECK(scene.triangles() == m.both.triangle_count());
    const accel::BruteAccel brute(m.both.view());
    const std::vector<accel_ray> rays = testing::three_kinds(m.both.bounds, 300, 3);
    std::vector<accel::Hit> closest(rays.size()), any(rays.size());
    brute.trace(rays, closest, {accel::Query::closest, accel::TracePath::scalar});
    brute.trace(rays, any, {accel::Query::any, accel::TracePath::scalar});
    const auto lists = testing::all_hits(brute, rays);
    const auto points = testing::query_points(m.both, 30, 4);
    std::vector<accel::PointHit> near(points.size());
    brute.closest_points(points, INFINITY, near);
    std::vector<float> xyz;
    for (const auto& p : points) xyz.insert(xyz.end(), {p.x, p.y, p.z});
    const std::vector<Ray> prays = to_public(rays);
    const RayArrays view = RayArrays::of(prays.data(), prays.size());

    for (const char* name : {"brute", "bvh-median", "bvh-sah", "lbvh", "kdtree", "auto"}) {
        CAPTURE(name);
        scene.build({name, 2});
        CHECK(scene.built());
        if (std::string(name) == "auto") CHECK_FALSE(scene.accel_reason().empty());
        else CHECK(scene.accel() == name);
        // Closest hit: t agrees with brute (the rayfile.md rule; prims may differ on exact ties).
        const std::vector<Hit> hits = scene.intersect(prays);
        std::size_t differ = 0, hit_count = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const Hit want = m.map(closest[i]);
            hit_count += want.hit();
            const bool ok = want.hit() == hits[i].hit() &&
                            (!want.hit() || (std::fabs(want.t - hits[i].t) <= 1e-4f * std::max(1.0f, want.t) && hits[i].geom < 2));
            differ += !ok;
        }
        CHECK(differ == 0);
        CHECK(hit_count > rays.size() / 3);
        // Any hit.
        const std::vector<bool> occ = scene.occluded(prays);
        for (std::size_t i = 0; i < rays.size(); ++i) REQUIRE(occ[i] == any[i].is_hit());
        // All hits: whole records, bit for bit, in rows of 4 with counts.
        std::vector<Hit> rows(rays.size() * 4);
        std::vector<std::int32_t> counts(rays.size(), -1);
        scene.intersect_all(view, 4, rows.data(), counts.data());
        std::size_t overflow = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            REQUIRE(counts[i] == std::int32_t(lists[i].size()));
            overflow += lists[i].size() > 4;
            for (std::size_t k = 0; k < 4; ++k) {
                const Hit want = k < lists[i].size() ? m.map(lists[i][k]) : Hit{};
                REQUIRE(same(rows[i * 4 + k], want));
            }
        }
        CHECK(overflow > 0);  // rays through both shapes and the torus twice
        // Closest point: whole records.
        const std::vector<ClosestPoint> cp = scene.closest_point(xyz);
        for (std::size_t i = 0; i < points.size(); ++i) {
            REQUIRE(cp[i].found());
            REQUIRE(std::bit_cast<std::uint32_t>(cp[i].distance) == std::bit_cast<std::uint32_t>(near[i].distance));
            const Hit g = m.map({0.0f, near[i].prim, 0.0f, 0.0f});
            REQUIRE((cp[i].geom == g.geom && cp[i].prim == g.prim));
            REQUIRE((cp[i].point[0] == near[i].point.x && cp[i].point[1] == near[i].point.y && cp[i].point[2] == near[i].point.z));
        }
        // Inside: as accel::inside_points on the oracle.
        const std::vector<bool> in = scene.inside(xyz);
        std::vector<std::uint8_t> want(points.size());
        accel::inside_points(brute, m.both.bounds, points, want);
        std::size_t inside_count = 0;
        for (std::size_t i = 0; i < points.size(); ++i) {
            REQUIRE(in[i] == (want[i] != 0));
            inside_count += in[i];
        }
        CHECK(inside_count > 0);
    }
}

TEST_CASE("api: rays as separate arrays (strides, one tnear/tfar for all), rows without room, NaN rays") {
    using namespace arbor;
    Scene scene;
    const engine::Mesh box = engine::make_box({-1, -1, -1}, {1, 1, 1});
    scene.add_mesh(std::vector<float>([&] {
                       std::vector<float> p;
                       for (std::size_t i = 0; i < box.vertex_count(); ++i) p.insert(p.end(), {box.x[i], box.y[i], box.z[i]});
                       return p;
                   }()),
                   box.indices);
    CHECK_FALSE(scene.built());
    // Origins packed, one direction for all (stride 0), tnear per ray, one tfar.
    const std::vector<float> org = {0.1f, 0.2f, -5.0f, 0.3f, -0.4f, -5.0f, 9.0f, 9.0f, -5.0f, NAN, 0.0f, -5.0f};
    const float dir[3] = {0.0f, 0.0f, 1.0f};
    const std::vector<float> tnear = {0.0f, 4.5f, 0.0f, 0.0f};
    RayArrays r;
    r.count = 4;
    r.origins = org.data();
    r.directions = dir;
    r.direction_stride = 0;
    r.tnear = tnear.data();
    r.tfar_value = 100.0f;
    std::vector<Hit> hits(4);
    scene.intersect(r, hits.data());  // built on first use, with the default options
    CHECK(scene.built());
    CHECK_FALSE(scene.accel().empty());
    CHECK(hits[0].t == doctest::Approx(4.0));
    CHECK(hits[1].t == doctest::Approx(6.0));  // starts past the front face
    CHECK_FALSE(hits[2].hit());
    CHECK_FALSE(hits[3].hit());  // NaN origin: a miss
    CHECK((hits[3].geom == invalid_id && hits[3].prim == invalid_id && std::isinf(hits[3].t)));
    // No room in the rows: counts only.
    std::vector<std::int32_t> counts(4);
    scene.intersect_all(r, 0, nullptr, counts.data());
    CHECK(counts == std::vector<std::int32_t>{2, 1, 0, 0});
    // Room for one: the nearer crossing, the count says two.
    std::vector<Hit> one(4);
    scene.intersect_all(r, 1, one.data(), counts.data());
    CHECK(one[0].t == doctest::Approx(4.0));
    CHECK(counts[0] == 2);
}

TEST_CASE("api: Scene::load, and errors as arbor::Error with their kind and a message naming the problem") {
    using namespace arbor;
    const auto paths = testing::model_paths();
    REQUIRE_MESSAGE(!paths.empty(), "the shared models (../shared/scenes/models) are needed");
    const std::string spot = testing::shared_scenes_dir() + "/models/spot.obj";
    Scene scene = Scene::load(spot);
    engine::Warnings w;
    CHECK(scene.triangles() == engine::load_obj(spot, w).triangle_count());
    CHECK(scene.meshes() == 1);
    const auto kind_of = [](auto&& f) {
        try {
            f();
        } catch (const Error& e) {
            CHECK(std::string(e.what()).find('\n') == std::string::npos);
            MESSAGE(std::string(e.what()));
            return int(e.kind());
        }
        return -1;
    };
    using K = Error::Kind;
    CHECK(kind_of([] { Scene::load("/nonexistent/model.obj"); }) == int(K::io));
    CHECK(kind_of([] { Scene::load("/tmp"); }) == int(K::io));
    CHECK(kind_of([] { Scene::load(ARBOR_SOURCE_DIR "/README.md"); }) == int(K::bad_file));
    CHECK(kind_of([&] { scene.build({"octree"}); }) == int(K::invalid_argument));
    CHECK(kind_of([&] { scene.build({"bvh-sah", -2}); }) == int(K::invalid_argument));
    CHECK(kind_of([&] { scene.build({"kdtree", 0, 1024}); }) == int(K::out_of_memory));
    const std::vector<float> p = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    CHECK(kind_of([&] { scene.add_mesh(p, {0, 1, 3}); }) == int(K::invalid_argument));
    CHECK(kind_of([&] { scene.add_mesh(nullptr, 3, 12, nullptr, 0); }) == int(K::invalid_argument));
    CHECK(kind_of([&] { scene.add_mesh(p.data(), 3, 8, nullptr, 0); }) == int(K::invalid_argument));
    CHECK(kind_of([&] { scene.closest_point(p, -1.0f); }) == int(K::invalid_argument));
    CHECK(kind_of([&] { scene.closest_point(p, NAN); }) == int(K::invalid_argument));
    CHECK(kind_of([&] { scene.inside(std::vector<float>{1, 2}); }) == int(K::invalid_argument));
    RayArrays r;
    r.count = 2;
    std::vector<Hit> h(2);
    CHECK(kind_of([&] { scene.intersect(r, h.data()); }) == int(K::invalid_argument));
    // The failed build left the scene usable: it builds again on the next query.
    scene.build({"bvh-sah"});
    CHECK(scene.accel() == "bvh-sah");
    CHECK(!version().empty());
    CHECK((kernel_set() == "avx512" || kernel_set() == "avx2" || kernel_set() == "sse4"));
}

TEST_CASE("api: batches from several threads at once and on 1 and 2 threads give the same answers") {
    using namespace arbor;
    const TwoMeshes m;
    const std::vector<Ray> rays = to_public(testing::three_kinds(m.both.bounds, 2000, 9));
    std::vector<float> xyz;
    for (const auto& p : testing::query_points(m.both, 40, 2)) xyz.insert(xyz.end(), {p.x, p.y, p.z});
    std::vector<std::vector<Hit>> per_threads;
    std::vector<std::vector<ClosestPoint>> cps;
    for (int threads : {1, 2}) {
        Scene scene;
        add_strided(scene, m.sphere);
        add_strided(scene, m.torus);
        scene.build({"bvh-sah", threads});
        per_threads.push_back(scene.intersect(rays));
        cps.push_back(scene.closest_point(xyz));
        // Four callers at once on the one scene.
        std::vector<std::vector<Hit>> got(4);
        std::vector<std::vector<bool>> ins(4);
        std::vector<std::thread> callers;
        for (int c = 0; c < 4; ++c)
            callers.emplace_back([&, c] {
                got[std::size_t(c)] = scene.intersect(rays);
                ins[std::size_t(c)] = scene.inside(xyz);
            });
        for (auto& t : callers) t.join();
        for (int c = 0; c < 4; ++c) {
            REQUIRE(got[std::size_t(c)].size() == rays.size());
            for (std::size_t i = 0; i < rays.size(); ++i) REQUIRE(same(got[std::size_t(c)][i], per_threads.back()[i]));
            CHECK(ins[std::size_t(c)] == ins[0]);
        }
    }
    for (std::size_t i = 0; i < rays.size(); ++i) REQUIRE(same(per_threads[0][i], per_threads[1][i]));
    for (std::size_t i = 0; i < cps[0].size(); ++i) REQUIRE(std::memcmp(&cps[0][i], &cps[1][i], sizeof(ClosestPoint)) == 0);
}
