// Closest point on the mesh (Accel::closest_points): the double-precision point-triangle kernel
// against an independent formulation, then every structure and layout against brute force, record
// for record, on the procedural shapes, every shared model and stiff inputs.
#include "accel/core/closest_point.h"
#include "accel/factory/make_accel.h"
#include "accel/structures/brute_accel.h"
#include "engine/procedural.h"
#include "query_check.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace arbor;
using accel::PointHit;
using accel::Vec3d;
using accel::Vec3f;

namespace {

#if defined(ARBOR_SANITIZED_BUILD)
constexpr std::size_t points_per_kind = 6;
#else
constexpr std::size_t points_per_kind = 24;
#endif

/// The distance from p to triangle (a, b, c) another way, in long double: the projection on the
/// plane when it falls inside the triangle, else the nearest of the three edges.
long double reference_distance(const Vec3f& pf, const Vec3f& af, const Vec3f& bf, const Vec3f& cf) {
    using L = long double;
    struct V {
        L x, y, z;
    };
    const auto to = [](const Vec3f& v) { return V{v.x, v.y, v.z}; };
    const auto sub = [](V a, V b) { return V{a.x - b.x, a.y - b.y, a.z - b.z}; };
    const auto dot = [](V a, V b) { return a.x * b.x + a.y * b.y + a.z * b.z; };
    const auto crs = [](V a, V b) { return V{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; };
    const V p = to(pf), a = to(af), b = to(bf), c = to(cf);
    const auto seg = [&](V s0, V s1) {
        const V d = sub(s1, s0);
        const L len2 = dot(d, d);
        L t = len2 > 0 ? dot(sub(p, s0), d) / len2 : 0;
        t = std::clamp<L>(t, 0, 1);
        const V q{s0.x + d.x * t, s0.y + d.y * t, s0.z + d.z * t};
        return std::sqrt(dot(sub(p, q), sub(p, q)));
    };
    L best = std::min({seg(a, b), seg(b, c), seg(c, a)});
    const V n = crs(sub(b, a), sub(c, a));
    const L n2 = dot(n, n);
    if (n2 > 0) {
        const L h = dot(sub(p, a), n) / n2;
        const V q{p.x - n.x * h, p.y - n.y * h, p.z - n.z * h};
        // Inside when q is on the inner side of all three edges.
        const bool in = dot(crs(sub(b, a), sub(q, a)), n) >= 0 && dot(crs(sub(c, b), sub(q, b)), n) >= 0 &&
                        dot(crs(sub(a, c), sub(q, c)), n) >= 0;
        if (in) best = std::min(best, std::fabs(h) * std::sqrt(n2));
    }
    return best;
}

void check_against_brute(const engine::Mesh& mesh, const std::vector<Vec3f>& points, bool every_width, float max_distance) {
    const auto structures = testing::query_structures(mesh.view(), every_width);
    std::vector<PointHit> ref(points.size());
    structures[0].accel->closest_points(points, max_distance, ref);  // brute
    REQUIRE(structures[0].name == "brute");
    std::size_t found = 0;
    for (const PointHit& h : ref) found += h.is_hit();
    if (std::isinf(max_distance)) CHECK(found == points.size());
    for (const auto& s : structures) {
        std::vector<PointHit> got(points.size());
        s.accel->closest_points(points, max_distance, got);
        std::size_t differ = 0;
        for (std::size_t i = 0; i < points.size(); ++i)
            if (!testing::same_point(got[i], ref[i])) {
                if (differ++ < 3)
                    MESSAGE(s.name << ": point " << i << " distance " << got[i].distance << " prim " << got[i].prim
                                   << ", brute " << ref[i].distance << " prim " << ref[i].prim);
            }
        CAPTURE(s.name);
        CHECK(differ == 0);
    }
}

}  // namespace

TEST_CASE("closest point: the kernel against the plane-or-edges distance in long double") {
    std::mt19937 rng(7);
    std::normal_distribution<float> g(0.0f, 1.0f);
    const auto rv = [&](float s) { return Vec3f{g(rng) * s, g(rng) * s, g(rng) * s}; };
    std::size_t checked = 0;
    for (int i = 0; i < 20000; ++i) {
        const float scale = std::pow(10.0f, float(i % 13) - 6.0f);  // 1e-6 .. 1e6
        Vec3f a = rv(scale), b = rv(scale), c = rv(scale);
        switch (i % 7) {  // degenerate triangles: collinear, two equal corners, a point
        case 1: c = a + (b - a) * 0.37f; break;
        case 2: c = b; break;
        case 3: b = a, c = a; break;
        default: break;
        }
        Vec3f p = rv(scale * 3.0f);
        switch (i % 5) {  // points at a vertex, on an edge, on the face, far away
        case 1: p = (i / 5) % 3 == 0 ? a : (i / 5) % 3 == 1 ? b : c; break;
        case 2: p = a + (c - a) * 0.25f; break;
        case 3: p = a * 0.2f + b * 0.3f + c * 0.5f; break;
        case 4: p = p * 1e4f; break;
        default: break;
        }
        const accel::TrianglePoint t = accel::closest_on_triangle(accel::to_double(p), accel::to_double(a),
                                                                  accel::to_double(b), accel::to_double(c));
        const long double want = reference_distance(p, a, b, c), got = std::sqrt((long double)t.dist2);
        const long double span = std::max({simd::length(b - a), simd::length(c - a), simd::length(c - b)});
        CAPTURE(i);
        REQUIRE(std::fabs(got - want) <= 1e-12L * (want + span));
        // The barycentric point is the reported point: its distance is the reported one.
        const Vec3d q = accel::to_double(a) * (1.0 - t.u - t.v) + accel::to_double(b) * t.u + accel::to_double(c) * t.v;
        const Vec3d d = q - accel::to_double(p);
        REQUIRE(std::fabs(std::sqrt(simd::dot(d, d)) - double(got)) <= 1e-12 * double(want + span));
        REQUIRE((t.u >= 0.0 && t.v >= 0.0 && t.u + t.v <= 1.0 + 1e-15));
        ++checked;
    }
    CHECK(checked == 20000);
}

TEST_CASE("closest point: every structure and width returns brute force's record on the procedural shapes") {
    const engine::Mesh shapes = testing::procedural_shapes();
    const auto points = testing::query_points(shapes, points_per_kind * 2, 11);
    check_against_brute(shapes, points, true, INFINITY);
    // A reach that leaves many points with nothing found; the boundary itself counts as within.
    check_against_brute(shapes, points, true, 0.02f * simd::length(shapes.bounds.extent()));
}

TEST_CASE("closest point: every structure returns brute force's record on every shared model") {
    testing::for_each_shared_mesh([](const std::string&, const engine::Mesh& mesh) {
        check_against_brute(mesh, testing::query_points(mesh, points_per_kind, 3), false, INFINITY);
    });
}

TEST_CASE("closest point: stiff inputs (non-finite points, reach, empty, far and tiny scenes, degenerate triangles)") {
    engine::Mesh sphere = engine::make_icosphere({0, 0, 0}, 1.0f, 2);
    const auto structures = testing::query_structures(sphere.view(), false);
    const std::vector<Vec3f> odd = {{NAN, 0, 0}, {INFINITY, 0, 0}, {0, -INFINITY, 0}, {0, 0, 5}};
    for (const auto& s : structures) {
        CAPTURE(s.name);
        std::vector<PointHit> out(odd.size());
        s.accel->closest_points(odd, INFINITY, out);
        for (int i = 0; i < 3; ++i) CHECK((!out[std::size_t(i)].is_hit() && std::isinf(out[std::size_t(i)].distance)));
        CHECK(out[3].is_hit());
        CHECK(out[3].distance == doctest::Approx(4.0).epsilon(0.01));
        s.accel->closest_points(odd, -1.0f, out);  // a negative reach finds nothing
        CHECK(!out[3].is_hit());
        s.accel->closest_points(odd, 3.9f, out);  // nothing within reach
        CHECK(!out[3].is_hit());
        // A vertex is its own closest point, at distance 0.
        const std::vector<Vec3f> at = {sphere.view().corner(7, 1)};
        s.accel->closest_points(at, 0.0f, out);
        CHECK(out[0].is_hit());
        CHECK(out[0].distance == 0.0f);
    }
    // Far and tiny scenes, degenerate triangles, an empty scene.
    engine::Mesh far = sphere, tiny = sphere, flat;
    for (auto& x : far.x) x += 1e6f;
    for (std::size_t i = 0; i < tiny.x.size(); ++i) tiny.x[i] *= 1e-6f, tiny.y[i] *= 1e-6f, tiny.z[i] *= 1e-6f;
    far.compute_bounds(), tiny.compute_bounds();
    for (int i = 0; i < 40; ++i) {  // collinear and coincident corners
        const float f = float(i);
        const std::uint32_t a = flat.add_vertex({f, 0, 0}), b = flat.add_vertex({f + 1, 0, 0}), c = flat.add_vertex({f + 2, 0, 0});
        flat.add_triangle(a, b, i % 2 ? b : c);
    }
    flat.compute_bounds();
    for (const engine::Mesh* m : {&far, &tiny, &flat}) check_against_brute(*m, testing::query_points(*m, 8, 5), true, INFINITY);
    engine::Mesh empty;
    for (accel::AccelKind kind : {accel::AccelKind::brute, accel::AccelKind::bvh_sah, accel::AccelKind::kdtree}) {
        const auto a = accel::make_accel(kind, empty.view());
        std::vector<PointHit> out(1);
        a->closest_points(std::vector<Vec3f>{{0, 0, 0}}, INFINITY, out);
        CHECK(!out[0].is_hit());
    }
}

TEST_CASE("closest point: searches started from the last point's answer keep brute force's record (chains of near points)") {
    // The fast structures start each search at the distance to the previous point's answer
    // (accel::warm_reach); chains of points a step apart, some on that answer itself, at scales
    // and offsets where the answer's float rounding matters, must still give brute's records.
    const engine::Mesh base = testing::procedural_shapes();
    std::mt19937 rng(5);
    std::normal_distribution<float> g(0.0f, 1.0f);
    for (const std::pair<float, float> so : {std::pair{1.0f, 0.0f}, {1e-5f, 0.0f}, {1e3f, 0.0f}, {1.0f, 1e5f}}) {
        const float scale = so.first, offset = so.second;  // no structured binding: CAPTURE's lambda takes it
        CAPTURE(scale);
        CAPTURE(offset);
        engine::Mesh mesh = base;
        for (auto* c : {&mesh.x, &mesh.y, &mesh.z})
            for (float& v : *c) v = v * scale + offset;
        mesh.bounds = {};
        for (std::size_t i = 0; i < mesh.x.size(); ++i) mesh.bounds.grow({mesh.x[i], mesh.y[i], mesh.z[i]});
        const float diag = simd::length(mesh.bounds.extent());
        const auto starts = testing::query_points(mesh, 8, 17);
        const accel::BruteAccel brute(mesh.view());
        std::vector<Vec3f> points;
        for (const Vec3f& s : starts) {
            Vec3f p = s;
            for (int k = 0; k < 24; ++k) {
                points.push_back(p);
                switch (k % 4) {
                case 0: break;  // the same point again
                case 1: p = p + Vec3f{g(rng), g(rng), g(rng)} * (1e-7f * diag); break;
                case 2: p = p + Vec3f{g(rng), g(rng), g(rng)} * (1e-3f * diag); break;
                default: {  // the answer of the point before: a point on the surface
                    std::vector<PointHit> h(1);
                    brute.closest_points(std::span(&p, 1), INFINITY, h);
                    p = h[0].point;
                }
                }
            }
        }
        check_against_brute(mesh, points, true, INFINITY);
        check_against_brute(mesh, points, true, 0.01f * diag);
    }
}
