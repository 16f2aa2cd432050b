// All hits along a ray (Accel::trace_all): every structure and layout gives brute force's list bit
// for bit; on the stiff cases every list keeps the double-precision oracle's rules triangle by
// triangle; crossing counts of closed meshes are exact away from edges and vertices.
#include "engine/procedural.h"
#include "query_check.h"
#include "stress/oracle.h"
#include "stress/stress_case.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <set>

using namespace arbor;
using accel::Hit;
using accel::Ray;
using accel::Vec3f;

namespace {

/// Sorted by (t, prim), no triangle twice, every t within the ray's range.
void check_list_rules(const Ray& r, const std::vector<Hit>& hits) {
    std::set<std::uint32_t> seen;
    for (std::size_t k = 0; k < hits.size(); ++k) {
        REQUIRE(seen.insert(hits[k].prim).second);
        REQUIRE((hits[k].t >= r.tnear && hits[k].t <= r.tfar));
        if (k) REQUIRE((hits[k - 1].t < hits[k].t || (hits[k - 1].t == hits[k].t && hits[k - 1].prim < hits[k].prim)));
    }
}

/// Every structure's lists equal brute force's, and their first hit is the closest hit.
void check_against_brute(const engine::Mesh& mesh, const std::vector<Ray>& rays, bool every_width) {
    const auto structures = testing::query_structures(mesh.view(), every_width);
    REQUIRE(structures[0].name == "brute");
    const auto ref = testing::all_hits(*structures[0].accel, rays);
    std::vector<Hit> closest(rays.size());
    structures[0].accel->trace(rays, closest, {accel::Query::closest, accel::TracePath::scalar});
    std::size_t crossings = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        check_list_rules(rays[i], ref[i]);
        crossings += ref[i].size();
        REQUIRE(ref[i].empty() == !closest[i].is_hit());
        if (!ref[i].empty()) REQUIRE(ref[i][0].t == closest[i].t);
    }
    CHECK(crossings > rays.size() / 10);
    for (std::size_t s = 1; s < structures.size(); ++s) {
        const auto got = testing::all_hits(*structures[s].accel, rays);
        std::size_t differ = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            bool same = got[i].size() == ref[i].size();
            for (std::size_t k = 0; same && k < ref[i].size(); ++k) same = testing::same_hit(got[i][k], ref[i][k]);
            if (!same && differ++ < 3)
                MESSAGE(structures[s].name << ": ray " << i << " has " << got[i].size() << " hits, brute " << ref[i].size());
        }
        CAPTURE(structures[s].name);
        CHECK(differ == 0);
    }
}

}  // namespace

TEST_CASE("all hits: every structure and width returns brute force's list on the procedural shapes") {
    const engine::Mesh shapes = testing::procedural_shapes();
#if defined(ARBOR_SANITIZED_BUILD)
    const std::size_t n = 60;
#else
    const std::size_t n = 400;
#endif
    std::vector<Ray> rays = testing::three_kinds(shapes.bounds, n, 21);
    // Short ranges cut the lists: hits outside [tnear, tfar] are not reported.
    for (std::size_t i = 0; i < rays.size(); i += 3) rays[i].tnear = 0.3f * simd::length(shapes.bounds.extent()), rays[i].tfar = 2.0f * rays[i].tnear;
    check_against_brute(shapes, rays, true);
}

TEST_CASE("all hits: every structure returns brute force's list on every shared model") {
#if defined(ARBOR_SANITIZED_BUILD)
    const std::size_t n = 12;
#else
    const std::size_t n = 60;
#endif
    testing::for_each_shared_mesh([&](const std::string&, const engine::Mesh& mesh) {
        check_against_brute(mesh, testing::three_kinds(mesh.bounds, n, 5), false);
    });
}

TEST_CASE("all hits: every list keeps the oracle's rules on the stiff cases") {
    // Triangle by triangle: each one the oracle says the ray certainly crosses is in the list,
    // none it rules out is, unsure ones (the band) may be either, and each t is within the
    // oracle's bound of the exact crossing (plus the rayfile.md tolerance).
    const auto cases = stress::make_stress_cases(stress::Size::small);
    REQUIRE(cases.size() > 20);
    std::size_t checked = 0, certain = 0;
    for (const auto& c : cases) {
        CAPTURE(c.name);
        const stress::Oracle oracle(c.mesh.view());
        const auto structures = testing::query_structures(c.mesh.view(), false);
        // Some rays of each case (the cases hold up to a few thousand): every 7th.
        std::vector<Ray> rays;
        for (std::size_t i = 0; i < c.rays.size(); i += 7) rays.push_back(c.rays[i]);
        for (const auto& s : structures) {
            CAPTURE(s.name);
            const auto lists = testing::all_hits(*s.accel, rays);
            for (std::size_t i = 0; i < rays.size(); ++i) {
                check_list_rules(rays[i], lists[i]);
                std::set<std::uint32_t> in;
                for (const Hit& h : lists[i]) {
                    in.insert(h.prim);
                    const stress::TriVerdict v = oracle.classify(rays[i], h.prim);
                    CAPTURE(i);
                    REQUIRE(v.kind != stress::TriVerdict::miss);
                    REQUIRE(std::fabs(double(h.t) - v.t) <= v.tol + 1e-4 * std::max(1.0, std::fabs(v.t)));
                }
                for (std::uint32_t t = 0; t < c.mesh.triangle_count(); ++t)
                    if (oracle.classify(rays[i], t).kind == stress::TriVerdict::hit) {
                        ++certain;
                        REQUIRE(in.count(t) == 1);
                    }
                ++checked;
            }
        }
    }
    CHECK(checked > 2000);
    CHECK(certain > 1000);
}

TEST_CASE("all hits: crossing counts through closed meshes are exact (odd from inside, even from outside)") {
    // A jittered icosphere, a torus and a box, each closed; rays from points inside (the centre of
    // the sphere and the box, a point in the torus tube) and from far outside, in random directions.
    struct Shape {
        engine::Mesh mesh;
        Vec3f inside;
    };
    std::vector<Shape> shapes;
    shapes.push_back({engine::make_icosphere({0.1f, 0.2f, 0.3f}, 1.3f, 3, 0.1f, 9), {0.1f, 0.2f, 0.3f}});
    shapes.push_back({engine::make_torus({0, 0, 0}, 2.0f, 0.6f, 48, 24), {2.0f, 0.0f, 0.0f}});
    shapes.push_back({engine::make_box({-1, -2, -3}, {1, 2, 3}), {0.0f, 0.0f, 0.0f}});
    std::mt19937 rng(4);
    std::normal_distribution<float> g(0.0f, 1.0f);
    for (const Shape& sh : shapes) {
        REQUIRE(stress::is_closed(sh.mesh));
        const stress::Oracle oracle(sh.mesh.view());
        const auto structures = testing::query_structures(sh.mesh.view(), true);
        std::vector<Ray> rays;
        std::vector<int> expect;
        const float far = 10.0f * simd::length(sh.mesh.bounds.extent());
        for (int i = 0; i < 200; ++i) {
            const Vec3f d = simd::normalize(Vec3f{g(rng), g(rng), g(rng)});
            const Ray r = i % 2 ? Ray{sh.inside, 0.0f, d, INFINITY} : Ray{sh.mesh.bounds.center() - d * far, 0.0f, d, INFINITY};
            const int n = oracle.crossings(r);
            if (n < 0) continue;  // in the band
            rays.push_back(r);
            expect.push_back(n);
            CHECK(n % 2 == i % 2);
        }
        REQUIRE(rays.size() > 150);
        for (const auto& s : structures) {
            CAPTURE(s.name);
            const auto lists = testing::all_hits(*s.accel, rays);
            for (std::size_t i = 0; i < rays.size(); ++i) CHECK(int(lists[i].size()) == expect[i]);
        }
    }
}
