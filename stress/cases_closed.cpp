// Watertightness: closed meshes (jittered subdivided spheres, a jittered torus, any closed model)
// traced from inside, aimed exactly at vertices and at points on edges.
#include "engine/procedural.h"
#include "stress/oracle.h"
#include "stress/stress_case.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <utility>

namespace arbor::stress {

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();

/// Every undirected edge once, in the order the triangles first use it.
std::vector<std::pair<std::uint32_t, std::uint32_t>> unique_edges(const engine::Mesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, bool> seen;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = m.indices[3 * t + k], b = m.indices[3 * t + (k + 1) % 3];
            if (seen.emplace(std::minmax(a, b), true).second) out.push_back({a, b});
        }
    return out;
}

/// Moves every vertex by up to `amount` in each coordinate (deterministic), keeping the mesh
/// closed: vertices are shared, so every triangle that uses one sees the same moved point.
void jitter_vertices(engine::Mesh& m, float amount, std::uint32_t seed) {
    std::uint64_t state = seed * 0x9E3779B97F4A7C15ull + 1;
    auto next = [&] {
        state ^= state << 13, state ^= state >> 7, state ^= state << 17;
        return float(state >> 40) / 16777216.0f * 2.0f - 1.0f;
    };
    for (std::size_t i = 0; i < m.vertex_count(); ++i) m.x[i] += amount * next(), m.y[i] += amount * next(), m.z[i] += amount * next();
    m.compute_bounds();
}

}  // namespace

bool is_closed(const engine::Mesh& mesh) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) ++directed[{mesh.indices[3 * t + k], mesh.indices[3 * t + (k + 1) % 3]}];
    for (const auto& [e, n] : directed) {
        const auto rev = directed.find({e.second, e.first});
        if (n != 1 || rev == directed.end() || rev->second != 1) return false;
    }
    return !directed.empty();
}

void add_rays_at_vertices_and_edges(StressCase& c, const Vec3f& origin, bool star, std::size_t stride) {
    const engine::Mesh& m = c.mesh;
    auto aim = [&](const Vec3f& target) {
        const Vec3f d = target - origin;
        if (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f) return;
        RayTag tag;
        tag.surface_t = star ? 1.0f : inf;  // o + 1*d is the target (exactly when the subtraction was exact)
        tag.parity = 1;                      // from inside: an odd number of crossings
        c.add({origin, 0.0f, d, inf}, tag);
        // Past the crossing at t = 1 the ray is outside; another hit must be a real surface. When
        // star-shaped, the ray is outside there, so it crosses an even number of times after it.
        RayTag cont;
        cont.continuation = true;
        cont.parity = star ? 0 : -1;
        c.add({origin, 1.001f, d, inf}, cont);
    };
    std::vector<bool> used(m.vertex_count(), false);
    for (std::uint32_t i : m.indices) used[i] = true;
    for (std::size_t i = 0; i < m.vertex_count(); i += stride)
        if (used[i]) aim({m.x[i], m.y[i], m.z[i]});
    const auto edges = unique_edges(m);
    for (std::size_t e = 0; e < edges.size(); e += stride) {
        const Vec3f a{m.x[edges[e].first], m.y[edges[e].first], m.z[edges[e].first]};
        const Vec3f b{m.x[edges[e].second], m.y[edges[e].second], m.z[edges[e].second]};
        aim((a + b) * 0.5f);
        aim(a + (b - a) * 0.125f);
        aim(a + (b - a) * 0.625f);
    }
}

void add_closed_cases(std::vector<StressCase>& out, Size size) {
    const bool full = size == Size::full;
    {
        // Spheres jittered radially around their centre stay star-shaped around it: scaling the
        // corners by positive factors keeps the sign of det(v0, v1, v2). The first one is centred
        // on (0,0,0), so rays from there have d = vertex exactly: they pass exactly through it.
        StressCase c;
        c.name = "watertight-sphere";
        c.what = "closed jittered icospheres; rays from inside exactly at vertices and edge points, and continuations";
        const int seeds = full ? 2 : 1;
        for (int seed = 1; seed <= seeds; ++seed) {
            const Vec3f center{10.0f * float(seed - 1), 0.0f, 0.0f};
            StressCase part;
            part.mesh = engine::make_icosphere(center, 2.0f, full ? 3 : 2, 0.25f, std::uint32_t(seed));
            add_rays_at_vertices_and_edges(part, center, true);
            for (const Vec3f& off : {Vec3f{0.3f, -0.2f, 0.1f}, Vec3f{-0.4f, 0.3f, -0.5f}})
                add_rays_at_vertices_and_edges(part, center + off, false, full ? 3 : 2);
            c.mesh.append(part.mesh);
            for (std::size_t i = 0; i < part.rays.size(); ++i) c.add(part.rays[i], part.tags[i]);
        }
        c.mesh.compute_bounds();
        out.push_back(std::move(c));
    }
    {
        // Axis-aligned closed boxes: their edges lie exactly in node-box faces (every structure's
        // boxes are unions of the triangles' boxes). Rays from inside at non-dyadic origins, aimed
        // at edge points and corners with inexact directions, pass within float rounding of those
        // edges: the box test must not cull the triangle the watertight test gives the hit to.
        StressCase c;
        c.name = "watertight-boxes";
        c.what = "closed axis-aligned boxes (edges on node-box faces); oblique rays from inside at edges and corners";
        const int n = full ? 3 : 2;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j)
                for (int k = 0; k < n; ++k) {
                    const Vec3f lo{float(i), float(j), float(k)};
                    StressCase part;
                    part.mesh = engine::make_box(lo, lo + Vec3f{0.75f, 0.75f, 0.75f});
                    // Convex: star-shaped around any interior point. Origins near a face make rays
                    // to that face's edges graze it (a tiny direction component along its normal).
                    for (const Vec3f& off : {Vec3f{0.3f, 0.41f, 0.29f}, Vec3f{0.1f, 0.6f, 0.37f}, Vec3f{0.52f, 0.13f, 0.66f},
                                             Vec3f{0.31f, 1e-3f, 0.43f}, Vec3f{5e-6f, 0.37f, 0.29f}, Vec3f{0.61f, 0.74999f, 3e-6f}})
                        add_rays_at_vertices_and_edges(part, lo + off, true);
                    c.mesh.append(part.mesh);
                    for (std::size_t r = 0; r < part.rays.size(); ++r) c.add(part.rays[r], part.tags[r]);
                }
        c.mesh.compute_bounds();
        out.push_back(std::move(c));
    }
    {
        // Not convex, not star-shaped: the core circle is inside the tube, other parts of the tube
        // may hide a target (then the first hit comes earlier, which the promise allows).
        StressCase c;
        c.name = "watertight-torus";
        c.what = "closed jittered torus (not star-shaped); rays from the core circle at vertices and edge points";
        c.mesh = engine::make_torus({0.5f, -0.25f, 0.125f}, 2.0f, 0.6f, full ? 48 : 16, full ? 24 : 8);
        jitter_vertices(c.mesh, 0.05f, 7);
        for (float a : {0.3f, 2.2f, 4.4f})
            add_rays_at_vertices_and_edges(c, Vec3f{0.5f + 2.0f * std::cos(a), -0.25f, 0.125f + 2.0f * std::sin(a)}, false, 2);
        out.push_back(std::move(c));
    }
}

StressCase make_closed_model_case(const engine::Mesh& mesh, const std::string& name, Size size) {
    if (!is_closed(mesh)) throw std::invalid_argument(name + ": not a closed mesh (an edge is not shared by exactly two triangles)");
    StressCase c;
    c.name = "watertight-" + name;
    c.what = "closed model " + name + "; rays from interior points at vertices and edge points";
    c.mesh = mesh;
    const Oracle oracle(mesh.view());
    // Interior points: cell centres of a grid over the bounds whose crossing count is odd along
    // three unrelated directions, none of them in the band.
    const accel::Bounds b = mesh.bounds;
    const Vec3f dirs[3] = {{0.5377f, 1.8339f, -2.2588f}, {0.8622f, 0.3188f, -1.3077f}, {-0.4336f, 0.3426f, 3.5784f}};
    std::vector<Vec3f> inside;
    const int n = 6;
    for (int i = 0; i < n && inside.size() < 3; ++i)
        for (int j = 0; j < n && inside.size() < 3; ++j)
            for (int k = 0; k < n && inside.size() < 3; ++k) {
                // Visit cells from the middle out (interleaved order), so points spread out.
                const int ii = (i * 5 + 2) % n, jj = (j * 5 + 3) % n, kk = (k * 5 + 1) % n;
                const Vec3f p = b.lo + b.extent() * Vec3f{(float(ii) + 0.5f) / n, (float(jj) + 0.5f) / n, (float(kk) + 0.5f) / n};
                bool odd = true;
                for (const Vec3f& d : dirs) {
                    const int x = oracle.crossings({p, 0.0f, d, inf});
                    odd = odd && x > 0 && x % 2 == 1;
                }
                if (odd) inside.push_back(p);
            }
    if (inside.empty()) throw std::invalid_argument(name + ": no interior point found");
    const std::size_t per_point = 2 * (mesh.vertex_count() + 3 * (mesh.triangle_count() * 3 / 2));
    const std::size_t budget = size == Size::full ? 20000 : 3000;
    const std::size_t stride = std::max<std::size_t>(1, per_point * inside.size() / budget + 1);
    for (const Vec3f& p : inside) add_rays_at_vertices_and_edges(c, p, false, stride);
    return c;
}

}  // namespace arbor::stress
