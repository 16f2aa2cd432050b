// One hit record, one tie rule (accel/core/hit_record.h): on rays that hit several triangles at
// exactly the same t (coplanar duplicate triangles, also at the shared vertices and edges of a
// flat grid), every structure and every path answers with the same record, bit for bit:
// the smallest t, on equal t the lowest prim. The expected record is worked out here from every
// triangle's own watertight test, independently of any structure; the test first checks that the
// rays do make ties (else it would prove nothing). Rays through the edges and corners of closed
// boxes, where the triangle test's own tie rule picks one triangle, are checked the same way.
#include "accel/factory/make_accel.h"
#include "accel/structures/brute_accel.h"
#include "accel/structures/kdtree_accel.h"
#include "accel/interface/trace.h"
#include "engine/mesh.h"
#include "engine/procedural.h"
#include "kd_simd_check.h"
#include "testing.h"
#include "wide_check.h"
#include "simd/ray_triangle.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <numeric>
#include <utility>
#include <random>

using namespace arbor;
using accel::Hit;
using accel::Ray;
using accel::Vec3f;

namespace {

/// An n x n grid of unit squares in the plane z = 0, two triangles each (alternating diagonals, so
/// that vertices are shared by 4, 6 or 8 triangles), numbered in a shuffled order: the lowest prim
/// at a vertex is then not the first triangle of any walk order.
engine::Mesh shuffled_grid(int n, std::uint32_t seed) {
    engine::Mesh m;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) m.add_vertex({float(i), float(j), 0.0f});
    std::vector<std::array<std::uint32_t, 3>> tris;
    const auto at = [n](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            if ((i + j) % 2 == 0) {
                tris.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                tris.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
            } else {
                tris.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
                tris.push_back({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
            }
        }
    std::mt19937 rng(seed);
    std::shuffle(tris.begin(), tris.end(), rng);
    for (const auto& t : tris) m.add_triangle(t[0], t[1], t[2]);
    m.compute_bounds();
    return m;
}

/// `mesh` with every triangle twice: triangle i and triangle i + count are the same corners (the
/// second copy's corners in rotated order, so the two watertight tests see the same triangle).
engine::Mesh doubled(const engine::Mesh& mesh) {
    engine::Mesh m = mesh;
    const std::size_t n = mesh.triangle_count();
    for (std::size_t i = 0; i < n; ++i) m.add_triangle(mesh.indices[3 * i], mesh.indices[3 * i + 1], mesh.indices[3 * i + 2]);
    m.compute_bounds();
    return m;
}

/// Rays down onto the grid through every vertex and every edge's midpoint, straight (exact ties:
/// every triangle through the point gives t = 1) and slanted (ties where the rounding agrees).
std::vector<Ray> grid_rays(int n) {
    std::vector<Ray> rays;
    for (int j = 0; j <= 2 * n; ++j)
        for (int i = 0; i <= 2 * n; ++i) {
            const Vec3f p{0.5f * float(i), 0.5f * float(j), 0.0f};
            rays.push_back({p + Vec3f{0, 0, 1}, 0.0f, {0, 0, -1}, INFINITY});
            rays.push_back({p + Vec3f{0, 0, -2}, 0.0f, {0, 0, 1}, INFINITY});  // from below
            rays.push_back({p + Vec3f{0.25f, -0.5f, 1}, 0.0f, {-0.25f, 0.5f, -1}, INFINITY});
        }
    return rays;
}

/// The expected closest record of each ray: every finite triangle's own scalar watertight test,
/// the smallest t, on equal t the lowest prim. `ties` counts rays with two or more triangles at
/// that smallest t.
std::vector<Hit> expected_hits(const accel::TriangleView& v, const std::vector<Ray>& rays, std::size_t& ties) {
    std::vector<Hit> out(rays.size());
    ties = 0;
    for (std::size_t r = 0; r < rays.size(); ++r) {
        const Ray& ray = rays[r];
        if (!accel::ray_is_traceable(ray)) continue;
        const simd::WoopShear s = simd::woop_shear(ray.dir);
        std::size_t at_best = 0;
        for (std::size_t t = 0; t < v.triangle_count(); ++t) {
            const simd::TriHit<float> h = simd::woop_test(ray.org, s, ray.tnear, ray.tfar, v.corner(t, 0), v.corner(t, 1), v.corner(t, 2));
            if (!h.hit) continue;
            if (h.t < out[r].t) out[r] = {h.t, std::uint32_t(t), h.u, h.v}, at_best = 1;
            else if (h.t == out[r].t) ++at_best;  // triangles in ascending order: the first stays
        }
        ties += at_best >= 2;
    }
    return out;
}

/// Every path of `a` (scalar, single, packet where offered, best) in chunks of 1024 and 5 rays
/// (partial packets) answers `expect` bit for bit, closest hits.
void check_all_paths(const accel::Accel& a, const std::vector<Ray>& rays, const std::vector<Hit>& expect, const std::string& name) {
    for (const auto path : {accel::TracePath::scalar, accel::TracePath::single, accel::TracePath::packet, accel::TracePath::best}) {
        if (path != accel::TracePath::best && !a.offer().has(path)) continue;
        for (const std::size_t chunk : {std::size_t(1024), std::size_t(5)}) {
            std::vector<Hit> got(rays.size());
            accel::trace_parallel(a, rays, got, accel::Query::closest, path, chunk);
            std::size_t bad = 0, first = rays.size();
            for (std::size_t i = 0; i < rays.size(); ++i)
                if (!testing::same_hit(got[i], expect[i]) && bad++ == 0) first = i;
            CAPTURE(name);
            CAPTURE(accel::to_string(path));
            CAPTURE(chunk);
            CAPTURE(first);
            CHECK(bad == 0);
        }
    }
}

/// Every structure, at every SIMD width and packet setting the SIMD-path tests use.
void check_every_structure(const engine::Mesh& mesh, const std::vector<Ray>& rays, const std::vector<Hit>& expect) {
    const auto view = mesh.view();
    check_all_paths(accel::BruteAccel(view), rays, expect, "brute");
    for (const std::uint32_t leaf : {1u, 4u}) {
        accel::BuildConfig cfg;
        cfg.bvh.max_leaf_size = leaf;
        for (const auto& b : testing::all_wide_bvhs(view, cfg)) check_all_paths(*b.accel, rays, expect, b.name);
        const auto lbvh = accel::make_accel(accel::AccelKind::lbvh, view, cfg);
        check_all_paths(*lbvh, rays, expect, "lbvh");
    }
    const auto kd = accel::make_kdtree_accel(view);
    for (const accel::BuildConfig& cfg : testing::kd_simd_configs())
        check_all_paths(*accel::make_kdtree_accel(kd->tree(), cfg), rays, expect, "kdtree");
}

}  // namespace

TEST_CASE("ties: rays through a grid's shared vertices and edges get the same record on every structure and path") {
    // The triangle test gives a shared vertex or edge point to one triangle of the grid (its tie
    // rule); with every triangle twice, that one ties with its copy at the same t.
    const engine::Mesh grid = doubled(shuffled_grid(6, 11));
    const std::vector<Ray> rays = grid_rays(6);
    std::size_t ties = 0;
    const std::vector<Hit> expect = expected_hits(grid.view(), rays, ties);
    // Straight rays through the 11 x 11 inner points hit (points of the border may be given to
    // the outside).
    CHECK(ties >= 2 * 11 * 11);
    check_every_structure(grid, rays, expect);
}

TEST_CASE("ties: coplanar duplicate triangles, the lower prim wins everywhere") {
    const engine::Mesh once = engine::make_icosphere({0, 0, 0}, 1.0f, 2, 0.1f, 3);
    const engine::Mesh twice = doubled(once);
    const std::vector<Ray> rays = testing::three_kinds(twice.bounds, 300, 5);
    std::size_t ties = 0;
    const std::vector<Hit> expect = expected_hits(twice.view(), rays, ties);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hits += expect[i].is_hit();
        if (expect[i].is_hit()) CHECK(expect[i].prim < once.triangle_count());  // the first copy
    }
    CHECK(hits > rays.size() / 4);
    CHECK(ties >= hits);  // every hit is a tie with the other copy
    check_every_structure(twice, rays, expect);
}

TEST_CASE("ties: the rule itself, one lane and a batch: smaller t wins, equal t the lower prim, a miss loses") {
    const float inf = INFINITY;
    const std::uint32_t none = accel::invalid_prim;
    const Hit miss{};
    CHECK(simd::closer(2.0f, 7u, miss));
    CHECK(simd::closer(2.0f, none - 1, miss));  // the highest prim still beats the miss record
    CHECK(simd::closer(1.0f, 9u, Hit{2.0f, 3u, 0, 0}));
    CHECK_FALSE(simd::closer(3.0f, 1u, Hit{2.0f, 3u, 0, 0}));
    CHECK(simd::closer(2.0f, 1u, Hit{2.0f, 3u, 0, 0}));
    CHECK_FALSE(simd::closer(2.0f, 3u, Hit{2.0f, 3u, 0, 0}));  // the same record is not replaced
    CHECK_FALSE(simd::closer(2.0f, 4u, Hit{2.0f, 3u, 0, 0}));
    CHECK(simd::closer(0.0f, 1u, Hit{-0.0f, 3u, 0, 0}));  // +0 and -0 tie
    // Lanes: prims above 2^31 compare unsigned, as in the scalar form.
    using T = simd::FloatV;
    using I = simd::IntOf<T>;
    constexpr std::size_t n = simd::lanes<T>;
    alignas(64) float t[n], bt[n];
    alignas(64) std::int32_t p[n], bp[n];
    for (std::size_t i = 0; i < n; ++i) {
        t[i] = float(i % 3), bt[i] = 1.0f;
        p[i] = std::int32_t(i % 2 ? 0x80000001u : 5u), bp[i] = std::int32_t(i % 4 < 2 ? 7u : none);
        if (i == n - 1) bt[i] = inf;
    }
    const std::uint32_t bits = simd::to_bits(simd::closer<T>(simd::load_lanes<T>(t), simd::load_lanes<I>(p),
                                                              simd::load_lanes<T>(bt), simd::load_lanes<I>(bp)));
    for (std::size_t i = 0; i < n; ++i) {
        CAPTURE(i);
        CHECK(bool(bits >> i & 1u) == simd::closer(t[i], std::uint32_t(p[i]), Hit{bt[i], std::uint32_t(bp[i]), 0, 0}));
    }
}

TEST_CASE("ties: behind the origin (tnear < 0), a box entered at the tied t is not culled") {
    // The grid rays reversed and given [tnear, tfar] = [-1e6, 1e6], directions scaled by 1, 3 and
    // 7 (inexact reciprocals): the closest hit is behind the origin, where the box tests' entry
    // distances may round a hair past the hit's t. A deferred child popped against a negative tfar
    // needs slab_test's room for negative exits (slab_accept), as when it was pushed; with a plain
    // `entry <= tfar` the scalar path culled the lower prim's leaf and answered the higher prim.
    const engine::Mesh grid = doubled(shuffled_grid(6, 23));
    std::vector<Ray> rays;
    for (const Ray& r : grid_rays(6))
        for (const float s : {1.0f, 3.0f, 7.0f}) rays.push_back({r.org, -1e6f, r.dir * -s, 1e6f});
    std::size_t ties = 0;
    const std::vector<Hit> expect = expected_hits(grid.view(), rays, ties);
    std::size_t behind = 0, hits = 0;
    for (const Hit& h : expect) behind += h.is_hit() && h.t < 0.0f, hits += h.is_hit();
    CHECK(behind == hits);
    CHECK(ties >= 3 * 2 * 11 * 11);
    check_every_structure(grid, rays, expect);
}

TEST_CASE("ties: rays through closed boxes' edges and corners get the same record on every structure and path") {
    // From outside through each corner and each edge's midpoint, towards the inside with a
    // direction whose dominant component is a power of two (the sheared frame then puts the
    // corner or edge exactly on the ray): the triangle test's tie rule picks one triangle there.
    for (const auto& [lo, hi] : {std::pair{Vec3f{0, 0, 0}, Vec3f{1, 1, 1}}, std::pair{Vec3f{5.123457f, -6.3f, 7.77f}, Vec3f{6.823457f, -5.37f, 9.97f}}}) {
        const engine::Mesh box = engine::make_box(lo, hi);
        const Vec3f mid = (lo + hi) * 0.5f;
        std::vector<Vec3f> points;
        for (int c = 0; c < 8; ++c) points.push_back({c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z});
        for (int axis = 0; axis < 3; ++axis)
            for (int c = 0; c < 4; ++c) {
                Vec3f p = mid;
                p[(axis + 1) % 3] = c & 1 ? hi[(axis + 1) % 3] : lo[(axis + 1) % 3];
                p[(axis + 2) % 3] = c & 2 ? hi[(axis + 2) % 3] : lo[(axis + 2) % 3];
                points.push_back(p);
            }
        std::vector<Ray> rays;
        for (const Vec3f& p : points)
            for (int k = 0; k < 3; ++k) {
                Vec3f d;
                for (int a = 0; a < 3; ++a) d[a] = (a == k ? 4.0f : a == (k + 1) % 3 ? 1.5f : 0.75f) * (mid[a] > p[a] ? 1.0f : -1.0f);
                rays.push_back({p - d, 0.0f, d, INFINITY});
            }
        std::size_t ties = 0;
        const std::vector<Hit> expect = expected_hits(box.view(), rays, ties);
        for (const Hit& h : expect) CHECK(h.is_hit());
        check_every_structure(box, rays, expect);
    }
}
