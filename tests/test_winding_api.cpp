// The public API's winding numbers, inside by method, signed distances and closed() (arbor.h):
// against the engine's exact sum and closest points, on every structure; overlapping parts,
// flipped and open meshes; errors; 1 and 2 threads.
#include "engine/procedural.h"
#include "query_check.h"
#include "winding_check.h"

#include <arbor/arbor.h>
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <limits>

using namespace arbor;
using accel::Vec3f;

namespace {

std::uint32_t add(Scene& s, const engine::Mesh& m) {
    std::vector<float> xyz;
    for (std::size_t i = 0; i < m.vertex_count(); ++i) xyz.insert(xyz.end(), {m.x[i], m.y[i], m.z[i]});
    return s.add_mesh(xyz, m.indices);
}

std::vector<float> flat(const std::vector<Vec3f>& points) {
    std::vector<float> out;
    for (const Vec3f& p : points) out.insert(out.end(), {p.x, p.y, p.z});
    return out;
}

const char* const structures[] = {"brute", "bvh-median", "bvh-sah", "lbvh", "kdtree", "auto"};

}  // namespace

TEST_CASE("api: winding_number exact and fast on every structure, inside and signed_distance by method") {
    // A sphere and a torus overlapping it (geom 0 and 1): 2 in the overlap, where the parity
    // (two surfaces crossed) says outside and the winding number inside.
    const engine::Mesh sphere = engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.05f, 2);
    const engine::Mesh torus = engine::make_torus({0.7f, 0.0f, 0.0f}, 0.8f, 0.4f, 24, 12);
    engine::Mesh both = sphere;
    both.append(torus);
    both.compute_bounds();
    const std::vector<Vec3f> points = testing::query_points(both, 30, 31);
    const std::vector<float> xyz = flat(points);
    const std::vector<Vec3f> overlap = {{-0.1f, 0.0f, 0.0f}, {-0.05f, 0.15f, 0.1f}, {0.0144f, 0.05f, 0.412f}};
    const std::vector<float> overlap_xyz = flat(overlap);
    for (const char* name : structures) {
        CAPTURE(name);
        Scene s;
        CHECK(add(s, sphere) == 0);
        CHECK(add(s, torus) == 1);
        s.build({name, 2});
        WindingOptions exact;
        exact.exact = true;
        const std::vector<double> we = s.winding_number(xyz, exact), wf = s.winding_number(xyz);
        REQUIRE(we.size() == points.size());
        double worst = 0.0;
        for (std::size_t i = 0; i < points.size(); ++i) {
            CHECK(std::fabs(we[i] - double(testing::oracle_winding(both.view(), points[i]))) <= 1e-9);
            worst = std::max(worst, std::fabs(wf[i] - we[i]));
        }
        CHECK(worst < 0.1);  // beta 2 (the tree's own bound is checked in test_winding.cpp)
        // The overlap: 2, inside by winding, outside by parity; signed distances follow.
        const std::vector<double> wo = s.winding_number(overlap_xyz);
        for (double w : wo) CHECK(std::fabs(w - 2.0) < 0.05);
        const std::vector<bool> in_w = s.inside(overlap_xyz, InsideMethod::winding),
                                in_p = s.inside(overlap_xyz, InsideMethod::parity);
        const std::vector<float> sd_w = s.signed_distance(overlap_xyz, InsideMethod::winding),
                                 sd_p = s.signed_distance(overlap_xyz);
        const std::vector<ClosestPoint> near = s.closest_point(overlap_xyz);
        for (std::size_t i = 0; i < overlap.size(); ++i) {
            CHECK(in_w[i]);
            CHECK_FALSE(in_p[i]);
            CHECK(sd_w[i] == -near[i].distance);
            CHECK(sd_p[i] == near[i].distance);
        }
        // Everywhere: inside by winding is w >= 1/2, by parity the existing inside(); signed
        // distances are the closest distance with that sign.
        const std::vector<bool> iw = s.inside(xyz, InsideMethod::winding), ip = s.inside(xyz, InsideMethod::parity),
                                ip_old = s.inside(xyz);
        const std::vector<float> dw = s.signed_distance(xyz, InsideMethod::winding),
                                 dp = s.signed_distance(xyz, InsideMethod::parity);
        const std::vector<ClosestPoint> cp = s.closest_point(xyz);
        for (std::size_t i = 0; i < points.size(); ++i) {
            CHECK(iw[i] == (wf[i] >= 0.5));
            CHECK(ip[i] == ip_old[i]);
            CHECK(dw[i] == (iw[i] ? -cp[i].distance : cp[i].distance));
            CHECK(dp[i] == (ip[i] ? -cp[i].distance : cp[i].distance));
        }
    }
}

TEST_CASE("api: winding inside of flipped, doubled and open meshes, the parity agreeing on closed ones") {
    const engine::Mesh sphere = engine::make_icosphere({0, 0, 0}, 1.0f, 4, 0.05f, 3);
    std::vector<float> xyz;
    for (int i = 0; i < 200; ++i) {  // along a line through the sphere, none near the surface
        const float t = -1.5f + 3.0f * float(i) / 199.0f;
        if (std::fabs(std::fabs(t) - 1.0f) > 0.1f) xyz.insert(xyz.end(), {t, 0.1f * t, -0.05f});
    }
    const auto check = [&](const engine::Mesh& m, double inside_value, bool parity_agrees) {
        Scene s;
        add(s, m);
        const std::vector<double> w = s.winding_number(xyz);
        const std::vector<bool> iw = s.inside(xyz, InsideMethod::winding), ip = s.inside(xyz, InsideMethod::parity);
        for (std::size_t i = 0; i < w.size(); ++i) {
            const bool in = std::fabs(xyz[3 * i]) < 1.0f;
            CHECK(std::fabs(w[i] - (in ? inside_value : 0.0)) < 0.05);
            CHECK(iw[i] == (in && inside_value >= 0.5));
            if (parity_agrees) CHECK(ip[i] == iw[i]);
        }
        return s.closed();
    };
    CHECK(check(sphere, 1.0, true));
    CHECK(check(testing::flipped(sphere), -1.0, false));       // inside out: -1, not inside
    CHECK_FALSE(check(testing::doubled(sphere), 2.0, false));  // every edge used four times: not closed
    // 2% of the faces deleted: open, and the winding number is still near 1 inside (the holes
    // take about 2% of the directions), near 0 outside.
    const engine::Mesh open = testing::without_faces(sphere, 20, 9);
    Scene s;
    add(s, open);
    CHECK_FALSE(s.closed());
    const std::vector<double> w = s.winding_number(xyz);
    const std::vector<bool> iw = s.inside(xyz, InsideMethod::winding);
    for (std::size_t i = 0; i < w.size(); ++i) {
        const bool in = std::fabs(xyz[3 * i]) < 1.0f;
        CHECK(std::fabs(w[i] - (in ? 1.0 : 0.0)) < 0.1);
        CHECK(iw[i] == in);
    }
}

TEST_CASE("api: closed() by vertex numbers, recomputed after add_mesh") {
    Scene s;
    CHECK(s.closed());  // no triangles: nothing is open
    add(s, engine::make_box({0, 0, 0}, {1, 1, 1}));
    CHECK(s.closed());
    add(s, engine::make_torus({3, 0, 0}, 1.0f, 0.3f, 12, 6));
    CHECK(s.closed());
    // The same box with every triangle's own three vertices (as an STL file holds them): positions
    // meet, vertex numbers do not.
    const engine::Mesh box = engine::make_box({5, 0, 0}, {6, 1, 1});
    std::vector<float> xyz;
    std::vector<std::uint32_t> idx;
    for (std::uint32_t v : box.indices) {
        idx.push_back(std::uint32_t(idx.size()));
        xyz.insert(xyz.end(), {box.x[v], box.y[v], box.z[v]});
    }
    Scene soup;
    soup.add_mesh(xyz, idx);
    CHECK_FALSE(soup.closed());
    s.add_mesh(xyz, idx);
    CHECK_FALSE(s.closed());
    // One triangle with a repeated vertex next to a closed box.
    Scene bad;
    add(bad, engine::make_box({0, 0, 0}, {1, 1, 1}));
    bad.add_mesh({0, 0, 0, 1, 0, 0}, {0, 0, 1});
    CHECK_FALSE(bad.closed());
    // The shared closed models are closed, the bunny (holes) is not.
    for (const std::string& name : {"spot.obj", "cow.obj", "stanford-bunny.obj"}) {
        CAPTURE(name);
        const Scene m = Scene::load(testing::shared_scenes_dir() + "/models/" + name);
        CHECK(m.closed() == (name != "stanford-bunny.obj"));
    }
}

TEST_CASE("api: winding errors name the argument, a non-finite point is NaN, 1 and 2 threads agree") {
    Scene s;
    add(s, engine::make_icosphere({0, 0, 0}, 1.0f, 5));
    const std::vector<float> xyz = {0, 0, 0, NAN, 0, 0, 0, 0, INFINITY, 3, 0, 0};
    for (double beta : {1.0, 0.5, -2.0, std::numeric_limits<double>::quiet_NaN()}) {
        WindingOptions o;
        o.beta = beta;
        try {
            (void)s.winding_number(xyz, o);
            FAIL("beta " << beta << " was accepted");
        } catch (const Error& e) {
            CHECK(e.kind() == Error::Kind::invalid_argument);
            CHECK(std::string(e.what()).find("beta") != std::string::npos);
        }
        CHECK_THROWS_AS((void)s.inside(xyz, InsideMethod::winding, o), Error);
        CHECK_NOTHROW((void)s.inside(xyz, InsideMethod::parity, o));  // parity reads no winding options
    }
    try {
        (void)s.inside(xyz, InsideMethod(7));
        FAIL("method 7 was accepted");
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::invalid_argument);
        CHECK(std::string(e.what()).find("method") != std::string::npos);
    }
    CHECK_THROWS_AS((void)s.signed_distance(xyz, InsideMethod(-1)), Error);
    CHECK_THROWS_AS((void)s.winding_number(std::vector<float>{1, 2}), Error);
    CHECK_THROWS_AS(s.winding_number(PointArrays{1, nullptr, 12}, nullptr), Error);
    // beta 2 (first-order dipoles): about 1% off here; exactly 1 and 0 with exact = true.
    const std::vector<double> w = s.winding_number(xyz);
    CHECK(std::fabs(w[0] - 1.0) < 0.05);
    CHECK(std::isnan(w[1]));
    CHECK(std::isnan(w[2]));
    CHECK(std::fabs(w[3]) < 0.01);
    WindingOptions exact;
    exact.exact = true;
    const std::vector<double> we = s.winding_number(xyz, exact);
    CHECK(std::fabs(we[0] - 1.0) < 1e-9);
    CHECK(std::isnan(we[1]));
    CHECK(std::fabs(we[3]) < 1e-9);
    const std::vector<bool> in = s.inside(xyz, InsideMethod::winding);
    CHECK(in[0]);
    CHECK_FALSE(in[1]);
    CHECK_FALSE(in[2]);
    const std::vector<float> sd = s.signed_distance(xyz, InsideMethod::winding);
    CHECK(sd[0] < 0.0f);
    CHECK(sd[1] == std::numeric_limits<float>::infinity());
    WindingOptions inf;
    inf.beta = std::numeric_limits<double>::infinity();
    const std::vector<double> all = s.winding_number(xyz, inf);
    CHECK(std::fabs(all[0] - 1.0) < 1e-9);

    // Threads: the same bits with 1 and 2 (chunks and the dipoles' parallel build).
    const engine::Mesh mesh = testing::without_faces(engine::make_icosphere({0, 0, 0}, 1.0f, 5, 0.1f, 4), 30, 2);
#if defined(ARBOR_SANITIZED_BUILD)
    constexpr std::size_t thread_points = 80;  // (brute's sum over every triangle per point: 10x slower there)
#else
    constexpr std::size_t thread_points = 400;
#endif
    const std::vector<float> pts = flat(testing::query_points(mesh, thread_points, 32));
    for (const char* name : structures) {
        CAPTURE(name);
        std::vector<std::vector<double>> answers;
        for (int threads : {1, 2}) {
            Scene t;
            add(t, mesh);
            t.build({name, threads});
            answers.push_back(t.winding_number(pts));
        }
        for (std::size_t i = 0; i < answers[0].size(); ++i)
            CHECK(std::bit_cast<std::uint64_t>(answers[0][i]) == std::bit_cast<std::uint64_t>(answers[1][i]));
    }
}
