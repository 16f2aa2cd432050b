// Precision: scenes translated far from the origin and scaled down, and secondary rays spawned
// from hit points (offset_ray.h) over coordinates from 1e-6 to 1e6.
#include "accel/structures/brute_accel.h"
#include "accel/core/offset_ray.h"
#include "engine/procedural.h"
#include "stress/stress_case.h"

#include <cstdio>
#include <random>

namespace arbor::stress {

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();

/// A closed jittered sphere, a torus and a ground grid, about 10 units across around the origin.
/// The sphere is first, so its triangles are [0, sphere_triangles).
engine::Mesh base_scene(bool full, std::size_t* sphere_triangles) {
    engine::Mesh m = engine::make_icosphere({0.5f, 0.0f, 0.25f}, 3.0f, full ? 3 : 2, 0.1f, 3);
    *sphere_triangles = m.triangle_count();
    m.append(engine::make_torus({3.0f, -0.5f, -2.0f}, 1.5f, 0.4f, full ? 32 : 12, full ? 12 : 6));
    for (int i = -2; i < 2; ++i)
        for (int j = -2; j < 2; ++j) m.append(engine::make_ground(-2.5f, 2.5f * float(i) + 1.25f, 2.5f * float(j) + 1.25f, 1.25f));
    m.compute_bounds();
    return m;
}

/// p * scale + offset, computed in double and rounded once.
Vec3f place(const Vec3f& p, double scale, double offset) {
    return {float(double(p.x) * scale + offset), float(double(p.y) * scale + offset), float(double(p.z) * scale + offset)};
}

std::string short_number(double v) {
    if (v == 0.0 || v == 1.0) return v == 0.0 ? "0" : "1";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0e", v);
    std::string s = buf;  // "1e+05" -> "1e5", "1e-06" -> "1e-6"
    const auto e = s.find('e');
    std::string mant = s.substr(0, e), exp = s.substr(e + 1);
    const bool neg = exp[0] == '-';
    exp = exp.substr(1);
    while (exp.size() > 1 && exp[0] == '0') exp.erase(0, 1);
    return mant + "e" + (neg ? "-" : "") + exp;
}

void add_placed(std::vector<StressCase>& out, bool full, const std::string& name, double scale, double offset) {
    StressCase c;
    c.name = name;
    c.what = "scene scaled by " + short_number(scale) + " and moved by " + short_number(offset) +
             " per axis; camera rays and rays from inside the closed sphere";
    std::size_t sphere_tris = 0;
    const engine::Mesh base = base_scene(full, &sphere_tris);
    c.mesh = base;
    for (std::size_t i = 0; i < c.mesh.vertex_count(); ++i) {
        const Vec3f p = place({base.x[i], base.y[i], base.z[i]}, scale, offset);
        c.mesh.x[i] = p.x, c.mesh.y[i] = p.y, c.mesh.z[i] = p.z;
    }
    c.mesh.compute_bounds();
    // Camera rays: eye and targets placed like the scene, directions computed in double.
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const Vec3f eye_base{4.0f, 3.0f, 12.0f};
    const Vec3f eye = place(eye_base, scale, offset);
    const std::size_t n = full ? 6000 : 500;
    for (std::size_t i = 0; i < n; ++i) {
        const double tx = 4.5 * u(rng) + 1.0, ty = 2.5 * u(rng), tz = 4.5 * u(rng);
        const Vec3f d{float((tx - eye_base.x) * scale), float((ty - eye_base.y) * scale), float((tz - eye_base.z) * scale)};
        c.add({eye, 0.0f, d, inf});
    }
    // Rays from the sphere's centre at its vertices and edge points: a closed surface (even when
    // rounding to a coarse grid has collapsed some of its triangles).
    StressCase sphere;
    sphere.mesh.x.assign(c.mesh.x.begin(), c.mesh.x.end());
    sphere.mesh.y.assign(c.mesh.y.begin(), c.mesh.y.end());
    sphere.mesh.z.assign(c.mesh.z.begin(), c.mesh.z.end());
    sphere.mesh.indices.assign(c.mesh.indices.begin(), c.mesh.indices.begin() + std::ptrdiff_t(3 * sphere_tris));
    add_rays_at_vertices_and_edges(sphere, place({0.5f, 0.0f, 0.25f}, scale, offset), false, full ? 2 : 4);
    for (std::size_t i = 0; i < sphere.rays.size(); ++i) c.add(sphere.rays[i], sphere.tags[i]);
    c.parity_prims = sphere_tris;
    out.push_back(std::move(c));
}

/// Secondary rays from the hit points of primary rays, as a renderer spawns them: reflection,
/// transmission (through the surface) and a random direction on the reflected side, each from
/// the barycentric hit point offset along the geometric normal (Wächter & Binder 2019).
void add_surface(std::vector<StressCase>& out, bool full, double scale) {
    StressCase c;
    c.name = "surface-" + short_number(scale);
    c.what = "secondary rays from hit points (offset_ray.h), coordinates ~" + short_number(scale) +
             ": never the own triangle again";
    std::size_t sphere_tris = 0;
    const engine::Mesh base = base_scene(full, &sphere_tris);
    c.mesh = base;
    // Coordinates of magnitude ~scale: scaled, and moved away from the origin by a few times that.
    for (std::size_t i = 0; i < c.mesh.vertex_count(); ++i) {
        const Vec3f p = place({base.x[i] + 9.0f, base.y[i] + 6.0f, base.z[i] - 7.0f}, scale, 0.0);
        c.mesh.x[i] = p.x, c.mesh.y[i] = p.y, c.mesh.z[i] = p.z;
    }
    c.mesh.compute_bounds();
    const accel::BruteAccel brute(c.mesh.view());
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    const Vec3f eye = place({13.0f, 9.0f, 5.0f}, scale, 0.0);
    const std::size_t n = full ? 3000 : 300;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3f target = place({9.5f + 4.5f * u(rng), 6.0f + 2.5f * u(rng), -7.0f + 4.5f * u(rng)}, scale, 0.0);
        const accel::Ray primary{eye, 0.0f, target - eye, inf};
        const accel::Hit h = brute.trace_one(primary, accel::Query::closest);
        if (!h.is_hit()) continue;
        const auto view = c.mesh.view();
        const Vec3f v0 = view.corner(h.prim, 0), v1 = view.corner(h.prim, 1), v2 = view.corner(h.prim, 2);
        const Vec3f p = v0 * (1.0f - h.u - h.v) + v1 * h.u + v2 * h.v;
        Vec3f ng = simd::cross(v1 - v0, v2 - v0);
        const float len = simd::length(ng);
        if (!(len > 0.0f) || !std::isfinite(len)) continue;
        ng = ng / len;
        if (simd::dot(ng, primary.dir) > 0.0f) ng = -ng;  // face the incoming ray
        const Vec3f dn = simd::normalize(primary.dir);
        RayTag tag;
        tag.source_prim = h.prim;
        const Vec3f reflect = dn - ng * (2.0f * simd::dot(dn, ng));
        const float tri_scale = accel::triangle_scale(v0, v1, v2);
        c.add({accel::offset_ray_origin(p, ng, tri_scale), 0.0f, reflect, inf}, tag);
        c.add({accel::offset_ray_origin(p, -ng, tri_scale), 0.0f, dn, inf}, tag);
        Vec3f rnd{normal(rng), normal(rng), normal(rng)};
        if (simd::dot(rnd, ng) < 0.0f) rnd = -rnd;
        if (simd::dot(rnd, rnd) > 0.0f) c.add({accel::offset_ray_origin(p, ng, tri_scale), 0.0f, rnd, inf}, tag);
    }
    out.push_back(std::move(c));
}

}  // namespace

void add_precision_cases(std::vector<StressCase>& out, Size size) {
    const bool full = size == Size::full;
    add_placed(out, full, "translate-0", 1.0, 0.0);
    add_placed(out, full, "translate-1e5", 1.0, 1e5);
    add_placed(out, full, "translate-1e6", 1.0, 1e6);
    add_placed(out, full, "translate-1e7", 1.0, 1e7);
    add_placed(out, full, "scale-1e-6", 1e-6, 0.0);
    for (double s : {1e-6, 1e-3, 1.0, 1e3, 1e6}) add_surface(out, full, s);
}

}  // namespace arbor::stress
