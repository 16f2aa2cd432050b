// Rays aimed at the edges that instances share in world space: a plane tiled by copies of one
// unit square (two triangles), each copy turned (and, in the mirrored tilings, mirrored) by one of
// the square's symmetries, scaled to its cell, and the whole moved. Every ray crosses the tiling
// once away from its outer border, so its count of crossings (intersect_all) must be 1: 0 is a
// leak, 2 a double count. Instances must leak nowhere and count twice no more often than the same
// tiling flattened. (Where a ray meets a shared edge exactly, the tie rule of the watertight test
// decides; on these tilings today's rule gives some such points to both triangles, flattened or
// not: the double counts are the rule's, and instances add none.)
#include "instance_scenes.h"

#include <arbor/arbor.h>
#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace arbor;
using testing::Transform;

namespace {

/// T = a * b for 3x4 affine transforms (b applied first).
Transform compose(const Transform& a, const Transform& b) {
    Transform t{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 4; ++j) {
            double s = j == 3 ? a[std::size_t(4 * i + 3)] : 0.0;
            for (int k = 0; k < 3; ++k) s += a[std::size_t(4 * i + k)] * b[std::size_t(4 * k + j)];
            t[std::size_t(4 * i + j)] = s;
        }
    }
    return t;
}

/// Symmetry k (0..7) of the unit square [0,1]^2 in z = 0: a turn by k % 4 quarter turns about its
/// centre, mirrored in x for k >= 4.
Transform symmetry(int k) {
    const int c[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};  // cos, sin of k quarter turns
    const double co = c[k % 4][0], si = c[k % 4][1], m = k >= 4 ? -1.0 : 1.0;
    // p -> R (M (p - h)) + h, h = (0.5, 0.5, 0), M = diag(m, 1, 1).
    const Transform r = {co * m, -si, 0, 0, si * m, co, 0, 0, 0, 0, 1, 0};
    const Transform to = {1, 0, 0, -0.5, 0, 1, 0, -0.5, 0, 0, 1, 0}, back = {1, 0, 0, 0.5, 0, 1, 0, 0.5, 0, 0, 1, 0};
    return compose(back, compose(r, to));
}

struct Counts {
    std::size_t rays = 0, leaks = 0, doubles = 0;
};

/// Tiles n x n cells of size w x h with copies of the unit square (cell (i, j) by symmetry
/// (i * 3 + j * 5) % 8), moves the tiling by `g`, and shoots `per_edge` rays at random points of
/// every interior grid line and at every interior grid vertex, from both sides.
Counts shoot(const Transform& g, double w, double h, int n, int per_edge, bool flattened, bool mirrors, std::uint32_t seed) {
    Scene s;
    engine::Mesh square;
    square.x = {0, 1, 1, 0}, square.y = {0, 0, 1, 1}, square.z = {0, 0, 0, 0};
    square.indices = {0, 1, 2, 0, 2, 3};
    square.compute_bounds();
    if (!flattened) testing::add(s, square);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const Transform cell = {w, 0, 0, i * w, 0, h, 0, j * h, 0, 0, 1, 0};
            const Transform t = compose(g, compose(cell, symmetry((i * 3 + j * 5) % (mirrors ? 8 : 4))));
            if (flattened) testing::add(s, testing::flatten(square, t));
            else s.add_instance(0, t.data());
        }
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::vector<std::array<double, 2>> targets;  // tiling coordinates
    for (int a = 1; a < n; ++a)
        for (int b = 0; b < n; ++b)
            for (int k = 0; k < per_edge; ++k) {
                targets.push_back({a * w, (b + u01(rng)) * h});  // vertical line x = a w
                targets.push_back({(b + u01(rng)) * w, a * h});  // horizontal line y = a h
            }
    for (int a = 1; a < n; ++a)
        for (int b = 1; b < n; ++b) targets.push_back({a * w, b * h});
    std::vector<Ray> rays;
    for (const auto& p : targets)
        for (const double side : {1.0, -1.0}) {
            const double local[3] = {p[0] + (u01(rng) - 0.5) * w, p[1] + (u01(rng) - 0.5) * h, side * (0.5 + u01(rng))};
            const auto world = [&](double x, double y, double z) {
                std::array<double, 3> r;
                for (int c = 0; c < 3; ++c)
                    r[std::size_t(c)] = g[std::size_t(4 * c)] * x + g[std::size_t(4 * c + 1)] * y + g[std::size_t(4 * c + 2)] * z +
                                        g[std::size_t(4 * c + 3)];
                return r;
            };
            const auto o = world(local[0], local[1], local[2]), t = world(p[0], p[1], 0.0);
            Ray r;
            for (int c = 0; c < 3; ++c) r.org[c] = float(o[std::size_t(c)]), r.dir[c] = float(t[std::size_t(c)] - o[std::size_t(c)]);
            rays.push_back(r);
        }
    const std::size_t k = 4;
    std::vector<Hit> hits(rays.size() * k);
    std::vector<std::int32_t> counts(rays.size());
    s.intersect_all(RayArrays::of(rays.data(), rays.size()), k, hits.data(), counts.data());
    Counts c;
    c.rays = rays.size();
    for (const std::int32_t m : counts) c.leaks += m == 0, c.doubles += m > 1;
    return c;
}

const Transform identity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};

/// The tiling placed by `t` in cells of w x h, flattened and instanced, with and without mirrored
/// cells: 0 leaks either way, and the instanced scene double-counts no more than the flattened one.
void check_tiling(const char* what, const Transform& t, double w, double h, std::uint32_t seed) {
    for (const bool mirrors : {false, true}) {
        CAPTURE(mirrors);
        const Counts flat = shoot(t, w, h, 6, 40, true, mirrors, seed);
        const Counts inst = shoot(t, w, h, 6, 40, false, mirrors, seed);
        MESSAGE(what, " tiling, mirrors ", mirrors, ", ", inst.rays, " rays: flattened ", flat.leaks, " leaks, ", flat.doubles,
                " double counts; instanced ", inst.leaks, " leaks, ", inst.doubles, " double counts");
        CHECK(flat.leaks == 0);
        CHECK(inst.leaks == 0);
        CHECK(inst.doubles <= flat.doubles);
    }
}

}  // namespace

TEST_CASE("instance edges: tilings by exact placements (quarter turns, mirrors, power-of-two scales)") {
    // Also in the plane x = 3 (a signed permutation of the axes), cells of 0.5 x 0.25.
    const Transform g = {0, 0, -1, 3, 1, 0, 0, -1, 0, 1, 0, 2};
    for (const Transform& t : {identity, g}) check_tiling("exact", t, 0.5, 0.25, 3);
}

TEST_CASE("instance edges: tilings by rotated, non-uniformly scaled placements") {
    check_tiling("general", testing::make_transform(0.7, {1, 2, 3}, {1, 1, 1}, {0.3, -0.2, 0.1}), 0.37, 0.61, 4);
}
