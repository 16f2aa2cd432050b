// Degenerate geometry: sliver and zero-area triangles, grazing rays, all centroids equal, copies
// of one triangle, one and two triangles, no triangle, non-finite vertices, coordinates near
// FLT_MAX.
#include "engine/procedural.h"
#include "stress/stress_case.h"

#include <cfloat>
#include <random>

namespace arbor::stress {

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();
constexpr float nan = std::numeric_limits<float>::quiet_NaN();

/// Rays from around the bounds towards random points inside them.
void add_random_rays(StressCase& c, const accel::Bounds& b, std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    const Vec3f center = b.center();
    const float r = simd::length(b.extent()) * 0.5f + 1e-3f;
    for (std::size_t i = 0; i < n; ++i) {
        Vec3f dir{normal(rng), normal(rng), normal(rng)};
        dir = simd::normalize(dir);
        const Vec3f o = center + dir * (2.0f * r);
        const Vec3f target = b.lo + b.extent() * Vec3f{u(rng), u(rng), u(rng)};
        c.add({o, 0.0f, target - o, inf});
    }
}

/// Rays from random points inside the bounds in random directions (safe for bounds near FLT_MAX).
void add_rays_inside(StressCase& c, const accel::Bounds& b, std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    for (std::size_t i = 0; i < n; ++i) {
        Vec3f o;
        for (int k = 0; k < 3; ++k) {
            const float f = u(rng);
            o[k] = b.lo[k] * (1.0f - f) + b.hi[k] * f;
        }
        c.add({o, 0.0f, Vec3f{normal(rng), normal(rng), normal(rng)}, inf});
    }
}

void add_slivers(std::vector<StressCase>& out, bool full) {
    StressCase c;
    c.name = "sliver-zero-area";
    c.what = "points, segments, slivers 1e-7 thin, needles, duplicates among a sphere; rays at them";
    c.mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 2, 0.1f, 2);
    engine::Mesh& m = c.mesh;
    const auto p = m.add_vertex({0.1f, 0.1f, 0.1f}), q = m.add_vertex({0.9f, 0.1f, 0.1f});
    const auto r = m.add_vertex({0.5f, 0.1f, 0.1f});           // on segment pq
    const auto s = m.add_vertex({0.5f, 0.1f + 1e-7f, 0.1f});   // a sliver with p, q
    const auto n0 = m.add_vertex({-3.0f, 0.3f, 0.0f}), n1 = m.add_vertex({3.0f, 0.3f, 0.0f});
    const auto n2 = m.add_vertex({0.0f, 0.3f + 1e-6f, 1e-6f});  // a needle through the sphere
    const int copies = full ? 40 : 8;
    for (int i = 0; i < copies; ++i) {
        m.add_triangle(p, p, p);
        m.add_triangle(p, q, r);
        m.add_triangle(p, q, s);
        m.add_triangle(q, p, s);
        m.add_triangle(n0, n1, n2);
    }
    m.compute_bounds();
    add_random_rays(c, m.bounds, full ? 3000 : 300, 12);
    for (float x : {0.1f, 0.2f, 0.5f, 0.75f, 0.9f, -2.0f, 0.0f, 2.5f}) {
        for (float dy : {0.0f, 2.5e-8f, 5e-8f, 1e-7f, 1.5e-7f, 1e-6f}) {
            c.add({{x, 0.1f + dy, 2.0f}, 0.0f, {0, 0, -1}, inf});
            c.add({{x, 0.3f + dy, 2.0f}, 0.0f, {0.0f, -0.0f, -1}, inf});
            c.add({{x, 2.0f, 0.1f + dy}, 0.0f, {0.01f, -1, 0.0f}, inf});
        }
    }
    out.push_back(std::move(c));
}

void add_grazing(std::vector<StressCase>& out, bool full) {
    StressCase c;
    c.name = "grazing";
    c.what = "rays in and nearly in the plane of a grid, rays tangent to a sphere";
    for (int i = -4; i < 4; ++i)
        for (int j = -4; j < 4; ++j) c.mesh.append(engine::make_ground(0.0f, float(i) + 0.5f, float(j) + 0.5f, 0.5f));
    c.mesh.append(engine::make_icosphere({0.0f, 2.0f, 0.0f}, 1.0f, full ? 3 : 2));
    c.mesh.compute_bounds();
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const std::size_t n = full ? 2000 : 200;
    for (std::size_t i = 0; i < n; ++i) {
        const float h = i % 4 == 0 ? 0.0f : (i % 4 == 1 ? 1e-7f : (i % 4 == 2 ? -1e-5f : 1e-3f)) * (1.0f + u(rng));
        const float slope = i % 3 == 0 ? 0.0f : (i % 3 == 1 ? 1e-6f : -1e-3f);
        const Vec3f o{-6.0f, h, 4.0f * u(rng)};
        c.add({o, 0.0f, {1.0f, slope, 0.37f * u(rng)}, inf});
    }
    // Tangent to the sphere: through a point p of it, perpendicular to the radius.
    for (std::size_t i = 0; i < n; ++i) {
        Vec3f nrm{u(rng), u(rng), u(rng)};
        nrm = simd::normalize(nrm);
        const Vec3f p = Vec3f{0.0f, 2.0f, 0.0f} + nrm;
        Vec3f t = simd::cross(nrm, Vec3f{u(rng), u(rng), u(rng)});
        t = simd::normalize(t);
        c.add({p - t * 3.0f, 0.0f, t, inf});
    }
    out.push_back(std::move(c));
}

void add_same_centroid(std::vector<StressCase>& out, bool full) {
    // Triangles (c + a, c - a, c + b) with |b_k| <= |a_k| have the box [c - |a|, c + |a|], so their
    // box centroids are all exactly c (dyadic values keep c +- a exact).
    StressCase c;
    c.name = "same-centroid";
    c.what = "every triangle's box centre is the same point; rays at random and through that point";
    std::mt19937 rng(31);
    std::uniform_int_distribution<int> q(1, 64), sgn(0, 1);
    const Vec3f center{1.0f, 2.0f, 3.0f};
    const int n = full ? 1000 : 100;
    for (int i = 0; i < n; ++i) {
        Vec3f a{0, 0, 0}, b{0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            a[k] = float(q(rng)) / 32.0f * (sgn(rng) ? 1.0f : -1.0f);
            b[k] = a[k] * float(q(rng) - 1) / 64.0f * (sgn(rng) ? 1.0f : -1.0f);
        }
        const auto i0 = c.mesh.add_vertex(center + a), i1 = c.mesh.add_vertex(center - a), i2 = c.mesh.add_vertex(center + b);
        c.mesh.add_triangle(i0, i1, i2);
    }
    c.mesh.compute_bounds();
    add_random_rays(c, c.mesh.bounds, full ? 2000 : 200, 32);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    for (int i = 0; i < (full ? 200 : 40); ++i) {
        Vec3f d{normal(rng), normal(rng), normal(rng)};
        c.add({center - d * 8.0f, 0.0f, d, inf});
    }
    out.push_back(std::move(c));

    StressCase copies;
    copies.name = "copies";
    copies.what = "thousands of copies of one triangle (equal boxes, equal centroids)";
    const auto v0 = copies.mesh.add_vertex({0, 0, 0}), v1 = copies.mesh.add_vertex({1, 0, 0}), v2 = copies.mesh.add_vertex({0, 1, 0});
    for (int i = 0; i < (full ? 5000 : 500); ++i) copies.mesh.add_triangle(v0, v1, v2);
    copies.mesh.compute_bounds();
    add_random_rays(copies, copies.mesh.bounds, full ? 400 : 80, 33);
    copies.add({{0.25f, 0.25f, 1.0f}, 0.0f, {0, 0, -1}, inf});
    out.push_back(std::move(copies));
}

void add_tiny_meshes(std::vector<StressCase>& out, bool full) {
    StressCase one;
    one.name = "one-triangle";
    one.what = "a single triangle; rays at random, at its vertices and edges, from both sides";
    one.mesh.add_vertex({0, 0, 0}), one.mesh.add_vertex({1, 0, 0}), one.mesh.add_vertex({0, 1, 0});
    one.mesh.add_triangle(0, 1, 2);
    one.mesh.compute_bounds();
    add_random_rays(one, one.mesh.bounds, full ? 2000 : 200, 41);
    for (const Vec3f& t : {Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}, Vec3f{0.5f, 0, 0}, Vec3f{0.5f, 0.5f, 0}, Vec3f{0, 0.25f, 0}})
        for (float side : {1.0f, -1.0f}) {
            const Vec3f o{0.25f, 0.125f, 2.0f * side};
            one.add({o, 0.0f, t - o, inf});
            one.add({{t.x, t.y, side}, 0.0f, {0.0f, -0.0f, -side}, inf});
        }
    out.push_back(std::move(one));

    // Two triangles sharing the diagonal of a unit square: a ray through the inside of the shared
    // edge crosses the surface, so it must hit.
    StressCase two;
    two.name = "two-triangles";
    two.what = "two triangles sharing an edge; rays through the shared edge must hit";
    two.mesh.add_vertex({0, 0, 0}), two.mesh.add_vertex({1, 0, 0}), two.mesh.add_vertex({1, 1, 0}), two.mesh.add_vertex({0, 1, 0});
    two.mesh.add_triangle(0, 1, 2), two.mesh.add_triangle(0, 2, 3);
    two.mesh.compute_bounds();
    add_random_rays(two, two.mesh.bounds, full ? 2000 : 200, 42);
    const int steps = full ? 64 : 16;
    for (int i = 1; i < steps; ++i) {
        const float f = float(i) / float(steps);  // on the diagonal (f, f, 0), exactly
        for (const Vec3f& o : {Vec3f{0.3f, -0.2f, 1.5f}, Vec3f{-1.0f, 2.0f, -0.75f}, Vec3f{f, f, 1.0f}}) {
            RayTag tag;
            tag.surface_t = 1.0f;
            two.add({o, 0.0f, Vec3f{f, f, 0.0f} - o, inf}, tag);
        }
    }
    out.push_back(std::move(two));

    StressCase empty;
    empty.name = "empty";
    empty.what = "no triangle at all";
    add_random_rays(empty, {{-1, -1, -1}, {1, 1, 1}}, 50, 43);
    empty.expected_dropped = 0;
    out.push_back(std::move(empty));
}

void add_nonfinite_vertices(std::vector<StressCase>& out, bool full) {
    StressCase c;
    c.name = "nonfinite-vertices";
    c.what = "NaN and +-Inf vertex coordinates: their triangles dropped, counted, never hit";
    c.mesh = engine::make_icosphere({0, 0, 0}, 1.0f, full ? 3 : 2, 0.1f, 4);
    engine::Mesh& m = c.mesh;
    const accel::Bounds finite_bounds = m.bounds;
    std::vector<bool> bad(m.vertex_count(), false);
    for (std::size_t i = 0; i < m.vertex_count(); i += 7) {
        const int k = int(i / 7) % 3;
        const float value = i % 3 == 0 ? nan : (i % 3 == 1 ? inf : -inf);
        (k == 0 ? m.x : k == 1 ? m.y : m.z)[i] = value;
        bad[i] = true;
    }
    std::int64_t dropped = 0;
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
        dropped += bad[m.indices[3 * t]] || bad[m.indices[3 * t + 1]] || bad[m.indices[3 * t + 2]];
    c.expected_dropped = dropped;
    add_random_rays(c, finite_bounds, full ? 3000 : 300, 51);
    out.push_back(std::move(c));
}

void add_near_flt_max(std::vector<StressCase>& out, bool full) {
    StressCase c;
    c.name = "near-flt-max";
    c.what = "boxes at +-3e38 and up to FLT_MAX around a unit box: no NaN, no crash; beyond float range is the band";
    c.mesh = engine::make_box({-3e38f, -3e38f, -3e38f}, {3e38f, 3e38f, 3e38f});
    c.mesh.append(engine::make_box({1e38f, 1e38f, 1e38f}, {FLT_MAX, FLT_MAX, FLT_MAX}));
    c.mesh.append(engine::make_box({-1, -1, -1}, {1, 1, 1}));
    c.mesh.compute_bounds();
    add_random_rays(c, {{-1, -1, -1}, {1, 1, 1}}, full ? 1000 : 100, 61);
    add_rays_inside(c, {{-2e38f, -2e38f, -2e38f}, {2e38f, 2e38f, 2e38f}}, full ? 1000 : 100, 62);
    out.push_back(std::move(c));
}

}  // namespace

void add_degenerate_cases(std::vector<StressCase>& out, Size size) {
    const bool full = size == Size::full;
    add_slivers(out, full);
    add_grazing(out, full);
    add_same_centroid(out, full);
    add_tiny_meshes(out, full);
    add_nonfinite_vertices(out, full);
    add_near_flt_max(out, full);
}

}  // namespace arbor::stress
