// Rays lying in the plane of a flat mesh: origins exactly on it, directions exactly in it. Every
// triangle of the plane is coplanar with such a ray and misses (the watertight test's determinant
// is 0); triangles that cross the plane, or stand on it with an edge in it, are hit. The boxes of
// the plane have no thickness across it and are culled (simd/ray_box.h, in_flat_slab): these
// cases check that the cull loses no hit on the triangles next to it.
#include "engine/procedural.h"
#include "stress/stress_case.h"

#include <cmath>
#include <random>

namespace arbor::stress {

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();

/// A quad of two triangles with corners a, b, c, d in order.
void add_quad(engine::Mesh& m, const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& d) {
    const std::uint32_t i = m.add_vertex(a), j = m.add_vertex(b), k = m.add_vertex(c), l = m.add_vertex(d);
    m.add_triangle(i, j, k);
    m.add_triangle(i, k, l);
}

/// A grid of 2 * cells^2 triangles in the plane y = 0 over [-cells/2, cells/2]^2 in x and z.
engine::Mesh flat_grid(int cells) {
    engine::Mesh m;
    for (int i = 0; i < cells; ++i)
        for (int j = 0; j < cells; ++j)
            m.append(engine::make_ground(0.0f, float(i - cells / 2) + 0.5f, float(j - cells / 2) + 0.5f, 0.5f));
    return m;
}

/// `n` rays with origins exactly on the plane y = 0 (random points of the grid, and its vertices
/// every fourth ray) and directions exactly in it; every eighth starts outside the grid.
void add_in_plane_rays(StressCase& c, float half, std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-half, half), angle(0.0f, 6.2831853f);
    for (std::size_t i = 0; i < n; ++i) {
        Vec3f o{u(rng), 0.0f, u(rng)};
        if (i % 4 == 1) o = {std::round(o.x), 0.0f, std::round(o.z)};
        if (i % 8 == 3) o.x = -half - 2.0f;
        const float a = angle(rng);
        c.add({o, i % 16 == 5 ? 0.25f : 0.0f, {std::cos(a), 0.0f, std::sin(a)}, inf});
    }
}

}  // namespace

void add_in_plane_cases(std::vector<StressCase>& out, Size size) {
    const bool full = size == Size::full;
    const int cells = full ? 32 : 8;
    const float half = float(cells) * 0.5f;
    const std::size_t n = full ? 4000 : 400;
    {
        StressCase c;
        c.name = "in-plane flat";
        c.what = "rays in the plane of a flat grid, the whole scene of no thickness: every ray misses";
        c.mesh = flat_grid(cells);
        c.mesh.compute_bounds();
        add_in_plane_rays(c, half, n, 31);
        out.push_back(std::move(c));
    }
    {
        StressCase c;
        c.name = "in-plane walls";
        c.what = "rays in the plane of a flat grid with walls crossing it and standing on it (an edge in the plane)";
        c.mesh = flat_grid(cells);
        // Crossing the plane (from y = -1 to 1) along x = 1.25 and along z = -0.75.
        add_quad(c.mesh, {1.25f, -1.0f, -half}, {1.25f, -1.0f, half}, {1.25f, 1.0f, half}, {1.25f, 1.0f, -half});
        add_quad(c.mesh, {-half, -1.0f, -0.75f}, {half, -1.0f, -0.75f}, {half, 1.0f, -0.75f}, {-half, 1.0f, -0.75f});
        // Standing on the plane, bottom edge in it: along x = -2.5 and along the grid line z = 2.
        add_quad(c.mesh, {-2.5f, 0.0f, -half}, {-2.5f, 0.0f, half}, {-2.5f, 1.0f, half}, {-2.5f, 1.0f, -half});
        add_quad(c.mesh, {-half, 0.0f, 2.0f}, {half, 0.0f, 2.0f}, {half, 1.0f, 2.0f}, {-half, 1.0f, 2.0f});
        // Hanging from above down to the plane, top edge away from it, bottom edge in it.
        add_quad(c.mesh, {3.0f, 2.0f, -1.0f}, {3.0f, 2.0f, 1.0f}, {3.0f, 0.0f, 1.0f}, {3.0f, 0.0f, -1.0f});
        c.mesh.compute_bounds();
        add_in_plane_rays(c, half, n, 37);
        out.push_back(std::move(c));
    }
}

}  // namespace arbor::stress
