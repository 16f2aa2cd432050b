// Rays aimed exactly at mesh vertices: the triangles sharing the vertex are hit at t that differ
// by an ulp or a few, and the nearer one's t can round below the computed entry distance of its
// leaf's box (simd/ray_box.h, box_tfar). Every structure (bvh-median, bvh-sah, lbvh, the kd-tree's
// walks), every width and every path (scalar, single, packet, best), in the default and the
// compact layout, must return brute force's closest hit bit for bit (t, prim, u, v), and any hits
// must agree with it on hit or miss: on every shared model, finely tessellated spheres, a flat
// axis-aligned grid (boxes of no thickness) and a terrain, from several origins each; half the
// rays end exactly at their hit (tfar = its t).
#include <doctest/doctest.h>

#include <cstring>
#include <random>
#include <sstream>

#include "accel/factory/make_accel.h"
#include "accel/kdtree/kdtree_build.h"
#include "accel/structures/brute_accel.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"
#include "testing.h"
#include "wide_check.h"

using namespace arbor;
using accel::Hit;
using accel::Ray;
using accel::Vec3f;

namespace {

#if defined(ARBOR_SANITIZED_BUILD)
constexpr std::size_t vertices_small = 100, vertices_big = 30;
#else
constexpr std::size_t vertices_small = 600, vertices_big = 200;
#endif

bool same_bits(const Hit& a, const Hit& b) { return std::memcmp(&a, &b, sizeof(Hit)) == 0; }

/// Rays from `origins` random points around the mesh (on a sphere 1.5 to 3 box radii from its
/// centre, and one in ten inside its box) aimed exactly at vertices used by triangles: all of
/// them when there are at most `max_vertices`, else that many spread over the numbering.
std::vector<Ray> vertex_rays(const engine::Mesh& mesh, std::size_t max_vertices, int origins, std::uint32_t seed) {
    std::vector<char> used(mesh.vertex_count(), 0);
    for (const std::uint32_t i : mesh.indices) used[i] = 1;
    std::vector<std::uint32_t> verts;
    for (std::uint32_t i = 0; i < used.size(); ++i)
        if (used[i]) verts.push_back(i);
    if (verts.size() > max_vertices) {
        std::vector<std::uint32_t> some;
        for (std::size_t k = 0; k < max_vertices; ++k) some.push_back(verts[k * verts.size() / max_vertices]);
        verts.swap(some);
    }
    std::mt19937 rng(seed);
    std::normal_distribution<float> n(0.0f, 1.0f);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const Vec3f c = mesh.bounds.center(), e = mesh.bounds.extent();
    const float radius = 0.5f * simd::length(e);
    std::vector<Ray> rays;
    for (int k = 0; k < origins; ++k)
        for (const std::uint32_t i : verts) {
            Vec3f o;
            if (rng() % 10 == 0) {
                o = {mesh.bounds.lo.x + u(rng) * e.x, mesh.bounds.lo.y + u(rng) * e.y, mesh.bounds.lo.z + u(rng) * e.z};
            } else {
                Vec3f d{n(rng), n(rng), n(rng)};
                d = d * (1.0f / simd::length(d));
                o = c + d * (radius * (1.5f + 1.5f * u(rng)));
            }
            const Vec3f target{mesh.x[i], mesh.y[i], mesh.z[i]};
            rays.push_back({o, 0.0f, target - o, INFINITY});
        }
    return rays;
}

std::vector<Hit> trace(const accel::Accel& a, const std::vector<Ray>& rays, accel::Query q, accel::TracePath path) {
    std::vector<Hit> hits(rays.size());
    a.trace(rays, hits, {q, path});
    return hits;
}

/// Every path `a` offers (and `best`) against brute's closest hits `ref`: closest hits bit for
/// bit, any hits by hit or miss. Adds "name/path: count" to `report` for each path that differs;
/// returns the number of closest hits that differ.
std::size_t check_accel(const accel::Accel& a, const std::string& name, const std::vector<Ray>& rays,
                        const std::vector<Hit>& ref, std::ostringstream& report) {
    std::size_t differ = 0;
    for (const auto path :
         {accel::TracePath::scalar, accel::TracePath::single, accel::TracePath::packet, accel::TracePath::best}) {
        if (path != accel::TracePath::best && !a.offer().runs(path, accel::Query::closest)) continue;
        const auto got = trace(a, rays, accel::Query::closest, path);
        std::size_t bad = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) bad += !same_bits(got[i], ref[i]);
        if (bad != 0) report << "  " << name << " " << accel::to_string(path) << ": " << bad << "\n";
        differ += bad;
        const auto any = trace(a, rays, accel::Query::any, path);
        const std::size_t occl = testing::count_occlusion_disagreements(any, ref);
        if (occl != 0) report << "  " << name << " " << accel::to_string(path) << " any hit: " << occl << "\n";
        differ += occl;
    }
    return differ;
}

/// Every structure, width, layout and path on `rays` against brute force.
/// Every other ray that hits ends exactly at its hit (tfar = brute's t: the triangle's box may
/// be entered just past tfar as computed).
void check_mesh(const engine::Mesh& mesh, std::vector<Ray> rays) {
    const auto v = mesh.view();
    const accel::BruteAccel brute(v);
    const auto ref = trace(brute, rays, accel::Query::closest, accel::TracePath::best);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hits += ref[i].is_hit();
        if (ref[i].is_hit() && i % 2 == 1) rays[i].tfar = ref[i].t;  // the same closest hit
    }
    CHECK(hits * 2 >= rays.size());  // vertex-aimed from outside: most rays hit
    std::ostringstream report;
    std::size_t differ = 0;
    for (const bool compact : {false, true}) {
        accel::BuildConfig cfg;
        cfg.compact = compact;
        for (const auto& b : testing::all_wide_bvhs(v, cfg))
            differ += check_accel(*b.accel, b.name + (compact ? "/compact" : ""), rays, ref, report);
    }
    // The kd-tree: one build, its rope walk over leaf blocks (scalar, single, packet) and its
    // cells as wide BVHs (both cell forms), at every width.
    const accel::KdTree tree = accel::build_kdtree(v);
    for (const auto walk : {accel::KdWalk::ropes, accel::KdWalk::cells, accel::KdWalk::tight_cells})
        for (const std::uint32_t w : testing::wide_widths()) {
            accel::BuildConfig cfg;
            cfg.kd_blocks.walk = walk;
            if (walk == accel::KdWalk::ropes)
                cfg.kd_blocks.width = w;
            else
                cfg.wide.width = w;
            const auto kd = accel::make_kdtree_accel(accel::KdTree(tree), cfg);
            differ += check_accel(*kd, std::string("kdtree/") + accel::kd_walk_name(walk) + "/w" + std::to_string(w),
                                  rays, ref, report);
        }
    if (differ != 0) MESSAGE("rays that differ from brute force, of " << rays.size() << ":\n" << report.str());
    CHECK(differ == 0);
}

/// An n x n grid of squares over [0, 1]^2, each split into two triangles: flat in the plane
/// z = 0.25 (boxes of no thickness), or with heights drawn from `seed` (a terrain).
engine::Mesh grid_mesh(int n, bool flat, std::uint32_t seed) {
    engine::Mesh m;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> h(0.0f, 0.2f);
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) m.add_vertex({float(i) / float(n), float(j) / float(n), flat ? 0.25f : h(rng)});
    const auto at = [n](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            m.add_triangle(at(i, j), at(i + 1, j), at(i + 1, j + 1));
            m.add_triangle(at(i, j), at(i + 1, j + 1), at(i, j + 1));
        }
    m.compute_bounds();
    return m;
}

}  // namespace

TEST_CASE("vertex-aimed rays: every shared model, every structure, width, layout and path equal brute force") {
    for (const auto& path : testing::model_paths()) {
        CAPTURE(path);
        engine::Warnings w;
        const engine::Mesh mesh = engine::load_obj(path, w);
        check_mesh(mesh, vertex_rays(mesh, mesh.triangle_count() > 30000 ? vertices_big : vertices_small, 2, 17));
    }
}

TEST_CASE("vertex-aimed rays: fine spheres and grids, every vertex from several origins") {
#if defined(ARBOR_SANITIZED_BUILD)
    const int subdivisions = 3, grid = 12;
#else
    const int subdivisions = 4, grid = 32;
#endif
    for (const float jitter : {0.0f, 0.2f}) {
        CAPTURE(jitter);
        const engine::Mesh sphere = engine::make_icosphere({0.3f, -0.2f, 0.1f}, 1.7f, subdivisions, jitter, 3);
        check_mesh(sphere, vertex_rays(sphere, sphere.vertex_count(), 2, 5));
    }
    for (const bool flat : {true, false}) {
        CAPTURE(flat);
        const engine::Mesh g = grid_mesh(grid, flat, 4);
        check_mesh(g, vertex_rays(g, g.vertex_count(), 2, 6));
    }
}
