// Instances placed by the identity: the two-level structure (accel/instances/) gives the plain
// scene's hits bit for bit (t, prim, u, v) on every structure, layout and path, for closest hits,
// any hits, all hits and closest points; and the public API's hits equal the plain scene's, with
// the instance id beside them.
#include "accel/factory/make_accel.h"
#include "accel/instances/instance_accel.h"
#include "engine/procedural.h"
#include "query_check.h"
#include "testing.h"

#include <arbor/arbor.h>
#include <doctest/doctest.h>

#include <bit>

using namespace arbor;
using accel::AccelKind;
using accel::TracePath;

namespace {

/// Mesh `m`'s own copy for a bottom structure.
std::unique_ptr<accel::InstanceMesh> copy(const engine::Mesh& m) {
    auto out = std::make_unique<accel::InstanceMesh>();
    out->x = m.x, out->y = m.y, out->z = m.z, out->indices = m.indices;
    const accel::TriangleView v = out->view();
    for (std::size_t t = 0; t < v.triangle_count(); ++t)
        if (v.triangle_is_finite(t)) out->bounds.grow(v.triangle_bounds(t));
    return out;
}

bool bits_equal(const accel::Hit& a, const accel::Hit& b) {
    return std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) && a.prim == b.prim &&
           std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
           std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v);
}

}  // namespace

TEST_CASE("instances: identity placements give the plain scene's hits bit for bit on every structure and path") {
    const std::vector<engine::Mesh> meshes = {engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.05f, 2),
                                              engine::make_torus({0.5f, 0, 0}, 1.0f, 0.3f, 24, 12),
                                              engine::make_box({-2, -1.5f, -2}, {2, -1.2f, 2})};
    engine::Mesh plain = meshes[0];
    for (std::size_t g = 1; g < meshes.size(); ++g) plain.append(meshes[g]);
    plain.compute_bounds();
    const auto rays = testing::three_kinds(plain.bounds, 1500, 7);
    const std::vector<accel::Vec3f> points = testing::query_points(plain, 100, 3);
    for (const AccelKind kind : {AccelKind::brute, AccelKind::bvh_median, AccelKind::bvh_sah, AccelKind::lbvh, AccelKind::kdtree}) {
        for (const accel::Layouts layouts : {accel::Layouts::simd, accel::Layouts::scalar}) {
            accel::BuildConfig cfg;
            cfg.layouts = layouts;
            const auto ref = accel::make_accel(kind, plain.view(), cfg);
            std::vector<accel::Bottom> bottoms;
            std::vector<accel::Placement> placements;
            for (std::size_t g = 0; g < meshes.size(); ++g) {
                accel::Bottom b;
                b.mesh = copy(meshes[g]);
                b.accel = accel::make_accel(kind, b.mesh->view(), cfg);
                bottoms.push_back(std::move(b));
                placements.push_back(accel::Placement::make(std::uint32_t(g), std::uint32_t(g), accel::Affine{}));
            }
            const accel::InstanceAccel two(kind, std::move(bottoms), std::move(placements));
            for (const TracePath path : {TracePath::scalar, TracePath::packet, TracePath::single}) {
                if (!ref->offer().has(path)) continue;
                CAPTURE(accel::to_string(kind));
                CAPTURE(accel::to_string(path));
                CAPTURE(int(layouts));
                std::vector<accel::Hit> a(rays.size()), b(rays.size());
                ref->trace(rays, a, {accel::Query::closest, path});
                two.trace(rays, b, {accel::Query::closest, path});
                std::size_t differ = 0, hits = 0;
                for (std::size_t i = 0; i < rays.size(); ++i) differ += !bits_equal(a[i], b[i]), hits += a[i].is_hit();
                CHECK(differ == 0);
                CHECK(hits > rays.size() / 3);
                ref->trace(rays, a, {accel::Query::any, path});
                two.trace(rays, b, {accel::Query::any, path});
                differ = 0;
                for (std::size_t i = 0; i < rays.size(); ++i) differ += a[i].is_hit() != b[i].is_hit();
                CHECK(differ == 0);
            }
            const auto all_a = testing::all_hits(*ref, rays), all_b = testing::all_hits(two, rays);
            std::size_t differ = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) {
                differ += all_a[i].size() != all_b[i].size();
                for (std::size_t k = 0; k < std::min(all_a[i].size(), all_b[i].size()); ++k)
                    differ += !bits_equal(all_a[i][k], all_b[i][k]);
            }
            CHECK(differ == 0);
            std::vector<accel::PointHit> pa(points.size()), pb(points.size());
            ref->closest_points(points, INFINITY, pa);
            two.closest_points(points, INFINITY, pb);
            differ = 0;
            for (std::size_t i = 0; i < points.size(); ++i) differ += !testing::same_point(pa[i], pb[i]);
            CHECK(differ == 0);
        }
    }
}

TEST_CASE("instances: through the public API, identity instances answer as the plain scene with inst set") {
    const engine::Mesh sphere = engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.05f, 2);
    const engine::Mesh torus = engine::make_torus({0.5f, 0, 0}, 1.0f, 0.3f, 24, 12);
    Scene plain, placed;
    for (const engine::Mesh* m : {&sphere, &torus}) {
        std::vector<float> xyz;
        for (std::size_t i = 0; i < m->vertex_count(); ++i) xyz.insert(xyz.end(), {m->x[i], m->y[i], m->z[i]});
        plain.add_mesh(xyz, m->indices);
        placed.add_mesh(xyz, m->indices);
    }
    const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    CHECK(placed.add_instance(1, id) == 0);
    CHECK(placed.add_instance(0, id) == 1);
    CHECK(placed.instances() == 2);
    accel::Bounds box;
    plain.bounds(&box.lo.x, &box.hi.x);
    const auto rays = testing::three_kinds(box, 800, 11);
    std::vector<Ray> pub(rays.size());
    std::memcpy(static_cast<void*>(pub.data()), rays.data(), rays.size() * sizeof(Ray));
    const auto a = plain.intersect(pub), b = placed.intersect(pub);
    std::size_t differ = 0, wrong_inst = 0;
    for (std::size_t i = 0; i < pub.size(); ++i) {
        differ += std::bit_cast<std::uint32_t>(a[i].t) != std::bit_cast<std::uint32_t>(b[i].t) || a[i].geom != b[i].geom ||
                  a[i].prim != b[i].prim || std::bit_cast<std::uint32_t>(a[i].u) != std::bit_cast<std::uint32_t>(b[i].u) ||
                  std::bit_cast<std::uint32_t>(a[i].v) != std::bit_cast<std::uint32_t>(b[i].v);
        CHECK(a[i].inst == invalid_id);
        const std::uint32_t want = !b[i].hit() ? invalid_id : (b[i].geom == 1 ? 0u : 1u);
        wrong_inst += b[i].inst != want;
    }
    CHECK(differ == 0);
    CHECK(wrong_inst == 0);
    // A mesh without instances is still placed, as it is, with inst = invalid_id.
    Scene half;
    for (const engine::Mesh* m : {&sphere, &torus}) {
        std::vector<float> xyz;
        for (std::size_t i = 0; i < m->vertex_count(); ++i) xyz.insert(xyz.end(), {m->x[i], m->y[i], m->z[i]});
        half.add_mesh(xyz, m->indices);
    }
    half.add_instance(1, id);
    const auto c = half.intersect(pub);
    differ = 0;
    for (std::size_t i = 0; i < pub.size(); ++i) {
        differ += a[i].t != c[i].t || a[i].geom != c[i].geom || a[i].prim != c[i].prim;
        wrong_inst += c[i].hit() && c[i].inst != (c[i].geom == 1 ? 0u : invalid_id);
    }
    CHECK(differ == 0);
    CHECK(wrong_inst == 0);
}
