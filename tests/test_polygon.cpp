// Polygons to triangles (engine/polygon.h, spec/rayfile.md): convex polygons fanned exactly as
// numbered, concave ones (an L, a star, a ring joined by a bridge) cut by ear clipping into k-2
// triangles that cover the polygon and nothing else, with the polygon's winding.
#include "engine/error.h"
#include "engine/obj_loader.h"
#include "engine/polygon.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

using namespace arbor;
using engine::Vec3f;
using Tri = std::array<std::uint32_t, 3>;

namespace {

std::vector<Tri> cut(const std::vector<Vec3f>& p) {
    std::vector<Tri> out;
    engine::triangulate_polygon(p, out);
    return out;
}

/// Signed area in the xy plane (counter-clockwise positive).
double area2d(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
    return 0.5 * ((double(b.x) - a.x) * (double(c.y) - a.y) - (double(b.y) - a.y) * (double(c.x) - a.x));
}

double polygon_area(const std::vector<Vec3f>& p) {
    double s = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3f& a = p[i];
        const Vec3f& b = p[(i + 1) % p.size()];
        s += double(a.x) * b.y - double(b.x) * a.y;
    }
    return 0.5 * s;
}

/// Even-odd point in polygon (xy plane).
bool inside(const std::vector<Vec3f>& p, double x, double y) {
    bool in = false;
    for (std::size_t i = 0, j = p.size() - 1; i < p.size(); j = i++) {
        if ((p[i].y > y) != (p[j].y > y) && x < (p[j].x - p[i].x) * (y - p[i].y) / (p[j].y - p[i].y) + p[i].x) in = !in;
    }
    return in;
}

/// k-2 triangles, each counter-clockwise (the polygon's winding) with its centroid inside the
/// polygon, areas summing to the polygon's.
void check_cover(const std::vector<Vec3f>& p) {
    const auto tris = cut(p);
    REQUIRE(tris.size() == p.size() - 2);
    double sum = 0.0;
    for (const Tri& t : tris) {
        const Vec3f &a = p[t[0]], &b = p[t[1]], &c = p[t[2]];
        const double area = area2d(a, b, c);
        CHECK(area >= 0.0);
        sum += area;
        if (area > 0.0) CHECK(inside(p, (double(a.x) + b.x + c.x) / 3, (double(a.y) + b.y + c.y) / 3));
    }
    CHECK(sum == doctest::Approx(polygon_area(p)).epsilon(1e-9));
}

}  // namespace

TEST_CASE("polygon: convex polygons are fanned from the first corner as rayfile.md numbers them") {
    std::vector<Vec3f> hexagon;
    for (int i = 0; i < 6; ++i) {
        const float a = float(i) * std::numbers::pi_v<float> / 3.0f;
        hexagon.push_back({std::cos(a), std::sin(a), 0.0f});
    }
    CHECK(engine::polygon_is_convex(hexagon));
    CHECK(cut(hexagon) == std::vector<Tri>{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}});
    // Collinear corners and clockwise winding are convex too.
    const std::vector<Vec3f> square_cw = {{0, 0, 0}, {0, 1, 0}, {0, 2, 0}, {2, 2, 0}, {2, 0, 0}};
    CHECK(engine::polygon_is_convex(square_cw));
    CHECK(cut(square_cw) == std::vector<Tri>{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}});
    // All corners on a line (zero Newell normal): fanned, k-2 triangles, none lost.
    const std::vector<Vec3f> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
    CHECK(cut(line).size() == 2);
}

TEST_CASE("polygon: concave polygons are cut by ear clipping and cover exactly the polygon") {
    const std::vector<Vec3f> ell = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
    CHECK_FALSE(engine::polygon_is_convex(ell));
    check_cover(ell);
    // The reflex corner first: fanning from it would be right, but the rule is convexity.
    check_cover({{1, 1, 0}, {1, 2, 0}, {0, 2, 0}, {0, 0, 0}, {2, 0, 0}, {2, 1, 0}});
    // A ten-pointed star.
    std::vector<Vec3f> star;
    for (int i = 0; i < 20; ++i) {
        const float a = float(i) * std::numbers::pi_v<float> / 10.0f, r = i % 2 ? 0.4f : 1.0f;
        star.push_back({r * std::cos(a), r * std::sin(a), 0.0f});
    }
    CHECK_FALSE(engine::polygon_is_convex(star));
    check_cover(star);
    // A ring: the outer square, a bridge to the inner square walked the other way, and back.
    const std::vector<Vec3f> ring = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}, {0, 0, 0}, {1, 1, 0},
                                     {1, 3, 0}, {3, 3, 0}, {3, 1, 0}, {1, 1, 0}};
    CHECK(polygon_area(ring) == doctest::Approx(12.0));
    check_cover(ring);
}

TEST_CASE("polygon: a self-intersecting pentagram still gives k-2 triangles and ends") {
    std::vector<Vec3f> pentagram;
    for (int i = 0; i < 5; ++i) {
        const float a = float(i * 2) * 2.0f * std::numbers::pi_v<float> / 5.0f;
        pentagram.push_back({std::cos(a), std::sin(a), 0.0f});
    }
    CHECK_FALSE(engine::polygon_is_convex(pentagram));  // it turns one way but winds twice
    CHECK(cut(pentagram).size() == 3);
}

TEST_CASE("polygon: a concave polygon in 3D keeps its winding in every triangle") {
    // The L in the plane x = 1, seen from +x it is counter-clockwise in (y, z).
    const std::vector<Vec3f> ell = {{1, 0, 0}, {1, 2, 0}, {1, 2, 1}, {1, 1, 1}, {1, 1, 2}, {1, 0, 2}};
    const auto tris = cut(ell);
    REQUIRE(tris.size() == 4);
    for (const Tri& t : tris) {
        const Vec3f n = simd::cross(ell[t[1]] - ell[t[0]], ell[t[2]] - ell[t[0]]);
        CHECK(n.x > 0.0f);
    }
}

TEST_CASE("loader: signed numbers and a concave face (a ring) in an OBJ file") {
    engine::Warnings w;
    const auto m = engine::load_obj_text("v +1 +2. +3.0\nv -1 +.5 0\nv 0 0 -0.5e+1\nf +1 2 3\n", "t.obj", "", w);
    REQUIRE(m.triangle_count() == 1);
    CHECK(m.x[0] == 1.0f);
    CHECK(m.y[0] == 2.0f);
    CHECK(m.z[0] == 3.0f);
    CHECK(m.y[1] == 0.5f);
    CHECK(m.z[2] == -5.0f);
    CHECK_THROWS_AS(engine::load_obj_text("v +-1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "t.obj", "", w), engine::InputError);
    CHECK_THROWS_AS(engine::load_obj_text("v ++1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "t.obj", "", w), engine::InputError);
    // The ring as one face: 10 corners, 8 triangles, area 12 (a fan would cover the hole too).
    const auto ring = engine::load_obj_text("v 0 0 0\nv 4 0 0\nv 4 4 0\nv 0 4 0\nv 1 1 0\nv 1 3 0\nv 3 3 0\nv 3 1 0\n"
                                            "f 1 2 3 4 1 5 6 7 8 5\n",
                                            "ring.obj", "", w);
    REQUIRE(ring.triangle_count() == 8);
    double area = 0.0;
    const auto v = ring.view();
    for (std::size_t t = 0; t < 8; ++t) area += area2d(v.corner(t, 0), v.corner(t, 1), v.corner(t, 2));
    CHECK(area == doctest::Approx(12.0));
}
