// The public C++ API's per-call options and the answers added beside the four queries:
// QueryOptions::threads (any count, above the cores too, gives the same bits), hit_normals, and
// closest_point with one max_distance per point.
#include <arbor/arbor.h>
#include <doctest/doctest.h>
#include <tbb/info.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>

#include "engine/procedural.h"
#include "api_shapes.h"
#include "query_check.h"

namespace {

using arbor::testing::TwoMeshes;
using arbor::testing::to_public;

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

int error_kind(const std::function<void()>& f, const char* expected_words) {
    try {
        f();
    } catch (const arbor::Error& e) {
        CHECK(std::string(e.what()).find(expected_words) != std::string::npos);
        return int(e.kind());
    }
    return -1;
}

}  // namespace

TEST_CASE("api: QueryOptions threads 1, 2, 3, 0 and above the cores give the same bits on every query") {
    using namespace arbor;
    const TwoMeshes m;
    const std::vector<Ray> rays = to_public(testing::three_kinds(m.both.bounds, 3000, 11));
    const RayArrays view = RayArrays::of(rays.data(), rays.size());
    std::vector<float> xyz;
    for (const auto& p : testing::query_points(m.both, 60, 5)) xyz.insert(xyz.end(), {p.x, p.y, p.z});
    Scene scene;
    m.add_to(scene);
    scene.build({"bvh-sah", 2});

    struct Answers {
        std::vector<Hit> hits, rows;
        std::vector<bool> occ, in;
        std::vector<std::int32_t> counts;
        std::vector<ClosestPoint> near;
        std::vector<float> normals;
    };
    const auto answers = [&](int threads) {
        const QueryOptions o{threads};
        Answers a;
        a.hits = scene.intersect(rays, o);
        a.occ = scene.occluded(rays, o);
        a.rows.resize(rays.size() * 3);
        a.counts.resize(rays.size());
        scene.intersect_all(view, 3, a.rows.data(), a.counts.data(), o);
        a.near = scene.closest_point(xyz, 0.5f, o);
        a.in = scene.inside(xyz, o);
        a.normals.resize(3 * rays.size());
        scene.hit_normals(a.hits.data(), a.hits.size(), sizeof(Hit), a.normals.data(), 3 * sizeof(float), o);
        return a;
    };
    const Answers ref = answers(1);
    std::size_t hit_count = 0;
    for (const Hit& h : ref.hits) hit_count += h.hit();
    CHECK(hit_count > rays.size() / 3);
    for (int threads : {2, 3, 0, 4 * tbb::info::default_concurrency() + 1}) {
        CAPTURE(threads);
        const Answers a = answers(threads);
        CHECK(same_bytes(a.hits, ref.hits));
        CHECK(a.occ == ref.occ);
        CHECK(same_bytes(a.rows, ref.rows));
        CHECK(a.counts == ref.counts);
        CHECK(same_bytes(a.near, ref.near));
        CHECK(a.in == ref.in);
        CHECK(same_bytes(a.normals, ref.normals));
    }
    // The build's threads are capped the same way: a count far above the cores builds and answers alike.
    scene.build({"bvh-sah", 1000});
    CHECK(same_bytes(scene.intersect(rays), ref.hits));

    using K = Error::Kind;
    std::vector<Hit> h(rays.size());
    CHECK(error_kind([&] { scene.intersect(view, h.data(), {-1}); }, "intersect: threads") == int(K::invalid_argument));
    CHECK(error_kind([&] { scene.inside(xyz, {-3}); }, "inside: threads") == int(K::invalid_argument));
    CHECK(error_kind([&] { scene.closest_point(xyz, 1.0f, {-1}); }, "closest_point: threads") ==
          int(K::invalid_argument));
}

TEST_CASE("api: hit_normals are the unit (v1-v0) x (v2-v0) of each hit's triangle, zeros for a miss") {
    using namespace arbor;
    const TwoMeshes m;
    const std::vector<Ray> rays = to_public(testing::random_rays_into(m.both.bounds, 2000, 4));
    Scene scene;
    m.add_to(scene);
    const std::vector<Hit> hits = scene.intersect(rays);
    // Normals interleaved with the hits, as the Python module stores them: a 36-byte record each.
    struct Record {
        Hit hit;
        float normal[3];
    };
    static_assert(sizeof(Record) == 36);
    std::vector<Record> rec(hits.size());
    for (std::size_t i = 0; i < hits.size(); ++i) rec[i].hit = hits[i], rec[i].normal[0] = NAN;
    scene.hit_normals(&rec[0].hit, rec.size(), sizeof(Record), rec[0].normal, sizeof(Record));
    std::size_t hit_count = 0, facing[2] = {0, 0}, away[2] = {0, 0};
    for (std::size_t i = 0; i < rec.size(); ++i) {
        const Hit& h = rec[i].hit;
        const float* n = rec[i].normal;
        if (!h.hit()) {
            CHECK((n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f));
            continue;
        }
        ++hit_count;
        const engine::Mesh& mesh = m.mesh(h.geom);
        const std::uint32_t* v = &mesh.indices[3 * h.prim];
        const double e1[3] = {mesh.x[v[1]] - mesh.x[v[0]], mesh.y[v[1]] - mesh.y[v[0]], mesh.z[v[1]] - mesh.z[v[0]]};
        const double e2[3] = {mesh.x[v[2]] - mesh.x[v[0]], mesh.y[v[2]] - mesh.y[v[0]], mesh.z[v[2]] - mesh.z[v[0]]};
        const double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0]};
        const double len = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        for (int k = 0; k < 3; ++k) REQUIRE(n[k] == doctest::Approx(c[k] / len).epsilon(1e-5));
        CHECK(std::fabs(double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2] - 1.0) < 1e-6);
        // Rays from outside enter these closed, consistently wound shapes at their first hit: per
        // shape, every normal faces the ray, or every normal faces away (the winding's choice).
        const float* d = rays[i].dir;
        const double dn = double(d[0]) * n[0] + double(d[1]) * n[1] + double(d[2]) * n[2];
        const double dl = std::sqrt(double(d[0]) * d[0] + double(d[1]) * d[1] + double(d[2]) * d[2]);
        facing[h.geom] += dn < -1e-4 * dl;
        away[h.geom] += dn > 1e-4 * dl;
    }
    CHECK(hit_count > rays.size() / 3);
    CHECK(facing[0] + away[0] > 0);
    CHECK(facing[1] + away[1] > 0);
    CHECK(std::min(facing[0], away[0]) == 0);
    CHECK(std::min(facing[1], away[1]) == 0);

    using K = Error::Kind;
    Hit bad = hits[0];
    bad.geom = 2, bad.prim = 0;
    float n[3];
    CHECK(error_kind([&] { scene.hit_normals(&bad, 1, sizeof(Hit), n, sizeof n); }, "geom 2") ==
          int(K::invalid_argument));
    bad.geom = 1, bad.prim = std::uint32_t(m.torus.triangle_count());
    CHECK(error_kind([&] { scene.hit_normals(&bad, 1, sizeof(Hit), n, sizeof n); }, "hit 0") ==
          int(K::invalid_argument));
}

TEST_CASE("api: closest_point with one max_distance per point answers as one call per distance") {
    using namespace arbor;
    const TwoMeshes m;
    Scene scene;
    m.add_to(scene);
    std::vector<float> xyz;
    for (const auto& p : testing::query_points(m.both, 40, 6)) xyz.insert(xyz.end(), {p.x, p.y, p.z});
    const std::size_t n = xyz.size() / 3;
    const float reaches[] = {0.0f, 0.05f, 0.5f, INFINITY};
    std::vector<std::vector<ClosestPoint>> each;
    for (float r : reaches) each.push_back(scene.closest_point(xyz, r));
    // Per point: a pattern of the four distances (runs of equal ones and changes at every point).
    std::vector<float> per(n);
    for (std::size_t i = 0; i < n; ++i) per[i] = reaches[(i / 3 + i * (i % 2)) % 4];
    std::vector<ClosestPoint> got(n);
    PointValues pv;
    pv.values = per.data();
    scene.closest_point({n, xyz.data(), 3 * sizeof(float)}, pv, got.data());
    std::size_t found = 0, cut = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t k =
            std::size_t(std::find(std::begin(reaches), std::end(reaches), per[i]) - std::begin(reaches));
        REQUIRE(std::memcmp(&got[i], &each[k][i], sizeof(ClosestPoint)) == 0);
        found += got[i].found();
        cut += !got[i].found() && each[3][i].found();
    }
    CHECK(found > 0);
    CHECK(cut > 0);  // the distances do cut some points off
    per[7] = -1.0f;
    CHECK(error_kind(
              [&] {
                  scene.closest_point({n, xyz.data(), 3 * sizeof(float)}, pv, got.data());
              },
              "max_distance[7]") == int(Error::Kind::invalid_argument));
}
