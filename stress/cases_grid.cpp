// Exact coordinates: integer-grid meshes traced along the axes (rays through vertices, along
// edges, in faces, with +0/-0 components), rays on node-box faces, and the axis-parallel vs
// oblique pair whose time columns compare the two.
#include "engine/procedural.h"
#include "stress/stress_case.h"

#include <map>
#include <random>
#include <tuple>

namespace arbor::stress {

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();

/// The surface of the box [0, n]^3 as a grid of unit squares (two triangles each, diagonals
/// alternating), vertices shared across faces so that the surface is closed.
engine::Mesh grid_box_surface(int n) {
    engine::Mesh m;
    std::map<std::tuple<int, int, int>, std::uint32_t> ids;
    auto vertex = [&](int x, int y, int z) {
        const auto [it, fresh] = ids.emplace(std::tuple{x, y, z}, 0u);
        if (fresh) it->second = m.add_vertex({float(x), float(y), float(z)});
        return it->second;
    };
    for (int axis = 0; axis < 3; ++axis)
        for (int side : {0, n})
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    auto at = [&](int a, int b) {
                        int p[3];
                        p[axis] = side, p[(axis + 1) % 3] = a, p[(axis + 2) % 3] = b;
                        return vertex(p[0], p[1], p[2]);
                    };
                    const std::uint32_t q0 = at(i, j), q1 = at(i + 1, j), q2 = at(i + 1, j + 1), q3 = at(i, j + 1);
                    if ((i + j) % 2) m.add_triangle(q0, q1, q2), m.add_triangle(q0, q2, q3);
                    else m.add_triangle(q0, q1, q3), m.add_triangle(q1, q2, q3);
                }
    return m;
}

/// An open grid of unit squares in the plane z = height over [0, n]^2.
engine::Mesh grid_plane(int n, float height) {
    engine::Mesh m;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) m.add_vertex({float(i), float(j), height});
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const auto a = std::uint32_t(j * (n + 1) + i), b = a + 1, c = b + std::uint32_t(n + 1), d = c - 1;
            if ((i + j) % 2) m.add_triangle(a, b, c), m.add_triangle(a, c, d);
            else m.add_triangle(a, b, d), m.add_triangle(b, c, d);
        }
    return m;
}

/// A unit direction along `axis` with `sign`, the other components +0 or -0 by `zero_bits`.
Vec3f axis_dir(int axis, float sign, int zero_bits) {
    Vec3f d{(zero_bits & 1) ? -0.0f : 0.0f, (zero_bits & 2) ? -0.0f : 0.0f, (zero_bits & 4) ? -0.0f : 0.0f};
    d[axis] = sign;
    return d;
}

void add_grid_axis(std::vector<StressCase>& out, bool full) {
    const int n = full ? 8 : 4;
    StressCase c;
    c.name = "grid-axis";
    c.what = "integer-grid closed box + inner plane; axis rays (+0/-0) through vertices, along edges, in faces";
    c.mesh = grid_box_surface(n);
    c.mesh.append(grid_plane(n, float(n / 2)));
    c.mesh.compute_bounds();
    const float nf = float(n);
    int zero_bits = 0;
    for (int axis = 0; axis < 3; ++axis)
        for (float sign : {1.0f, -1.0f})
            for (int p = 0; p <= 2 * n; ++p)
                for (int q = 0; q <= 2 * n; ++q)
                    for (float along : {-1.0f, 0.0f, 1.0f, nf / 2, nf - 0.5f}) {
                        Vec3f o;
                        o[axis] = sign > 0 ? along : nf - along;
                        o[(axis + 1) % 3] = 0.5f * float(p);
                        o[(axis + 2) % 3] = 0.5f * float(q);
                        const Vec3f d = axis_dir(axis, sign, zero_bits++ & 7);
                        const bool inside = o.x > 0 && o.x < nf && o.y > 0 && o.y < nf && o.z > 0 && o.z < nf;
                        RayTag tag;
                        const float wall = sign > 0 ? nf - o[axis] : o[axis];
                        if (inside) tag.surface_t = wall;  // a closed box: the wall at the latest
                        c.add({o, 0.0f, d, inf}, tag);
                        // Range ends exactly on a surface: tfar on the wall (inclusive), tnear on
                        // the inner plane or a grid plane.
                        if (inside) c.add({o, 0.0f, d, wall});
                        if (inside && p % 2 == 0) c.add({o, 1.0f, d, inf});
                    }
    out.push_back(std::move(c));
}

void add_box_faces(std::vector<StressCase>& out, bool full) {
    // Closed boxes [i, i + 0.75]^3: every node box of every structure has its faces on these
    // planes, so rays in these planes run exactly along node-box faces.
    const int n = full ? 3 : 2;
    StressCase c;
    c.name = "box-faces";
    c.what = "separate closed boxes; axis rays in their face planes, rays ending or starting on faces, aimed at corners";
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k)
                c.mesh.append(engine::make_box({float(i), float(j), float(k)}, {i + 0.75f, j + 0.75f, k + 0.75f}));
    c.mesh.compute_bounds();
    std::vector<float> planes;
    for (int i = 0; i < n; ++i) planes.insert(planes.end(), {float(i), i + 0.375f, i + 0.75f});
    int zero_bits = 0;
    for (int axis = 0; axis < 3; ++axis)
        for (float sign : {1.0f, -1.0f})
            for (float p : planes)
                for (float q : planes) {
                    Vec3f o;
                    o[(axis + 1) % 3] = p, o[(axis + 2) % 3] = q;
                    const Vec3f d = axis_dir(axis, sign, zero_bits++ & 7);
                    o[axis] = sign > 0 ? -1.0f : float(n) + 1.0f;
                    c.add({o, 0.0f, d, inf});
                    // From the middle of a box (inside it when p, q are interior too).
                    o[axis] = 0.375f;
                    const float frac_p = p - float(int(p)), frac_q = q - float(int(q));
                    RayTag tag;
                    if (frac_p == 0.375f && frac_q == 0.375f) tag.surface_t = 0.375f;
                    c.add({o, 0.0f, d, inf}, tag);
                    // Starting exactly on a face plane.
                    o[axis] = 0.75f;
                    c.add({o, 0.0f, d, inf});
                }
    // Oblique rays from dyadic points at box corners and edge midpoints: d = target - o is exact.
    const Vec3f eyes[] = {{-2.0f, -1.5f, -3.0f}, {4.5f, -2.0f, 1.25f}, {1.5f, 5.0f, -2.5f}};
    for (const Vec3f& eye : eyes)
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j)
                for (int k = 0; k < n; ++k)
                    for (const Vec3f& corner : {Vec3f{0, 0, 0}, Vec3f{0.75f, 0.75f, 0.75f}, Vec3f{0.375f, 0, 0.75f},
                                                Vec3f{0.75f, 0.375f, 0}, Vec3f{0.375f, 0.375f, 0}}) {
                        const Vec3f target = Vec3f{float(i), float(j), float(k)} + corner;
                        c.add({eye, 0.0f, target - eye, inf});
                        c.add({eye, 0.0f, target - eye, 1.0f});  // tfar exactly on the target
                    }
    out.push_back(std::move(c));
}

/// Spheres and tori in [0, 32]^3, so that integer planes cut through them.
engine::Mesh speed_scene(bool full) {
    engine::Mesh m;
    const int n = full ? 3 : 2;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const float x = 4.0f + 24.0f * float(i) / float(n - 1), y = 4.0f + 24.0f * float(j) / float(n - 1);
            m.append(engine::make_icosphere({x, y, 10.0f}, 3.5f, full ? 2 : 1, 0.1f, std::uint32_t(i * n + j + 1)));
            m.append(engine::make_torus({x, y, 22.0f}, 3.0f, 1.0f, full ? 24 : 8, full ? 12 : 6));
        }
    m.compute_bounds();
    return m;
}

void add_axis_vs_oblique(std::vector<StressCase>& out, bool full) {
    StressCase axis, oblique;
    axis.name = "axis-parallel";
    axis.what = "axis rays (+0/-0) from origins on split planes (vertex coordinates, integer planes); time vs oblique";
    oblique.name = "oblique";
    oblique.what = "the same origins as axis-parallel, random oblique directions";
    axis.mesh = speed_scene(full);
    oblique.mesh = axis.mesh;
    const engine::Mesh& m = axis.mesh;
    std::mt19937 rng(11);
    std::uniform_int_distribution<std::uint32_t> pick(0, std::uint32_t(m.vertex_count() - 1));
    std::uniform_int_distribution<int> grid(0, 32), axis_pick(0, 2), bits(0, 7);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    const std::size_t count = full ? 8000 : 400;
    for (std::size_t r = 0; r < count; ++r) {
        // Each origin coordinate is a vertex coordinate (a candidate split plane of a kd-tree and
        // a box face of some BVH node) or an integer plane (an LBVH grid plane).
        Vec3f o;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = pick(rng);
            o[k] = r % 2 ? (k == 0 ? m.x[v] : k == 1 ? m.y[v] : m.z[v]) : float(grid(rng));
        }
        const int a = axis_pick(rng);
        const Vec3f d = axis_dir(a, r % 4 < 2 ? 1.0f : -1.0f, bits(rng));
        axis.add({o, 0.0f, d, inf});
        Vec3f od{normal(rng), normal(rng), normal(rng)};
        od = simd::normalize(od);
        oblique.add({o, 0.0f, od, inf});
    }
    out.push_back(std::move(axis));
    out.push_back(std::move(oblique));
}

}  // namespace

void add_grid_cases(std::vector<StressCase>& out, Size size) {
    const bool full = size == Size::full;
    add_grid_axis(out, full);
    add_box_faces(out, full);
    add_axis_vs_oblique(out, full);
}

}  // namespace arbor::stress
