// Accel::refit of every structure that has one (the binary BVHs on their scalar and SIMD layouts at
// every width, brute), against fresh builds over the new positions: every path and every query bit
// for bit over the steps of a deforming model (testing::deforming_model); the refitted boxes contain what they should; the
// result is the same on 1 and 2 threads; the kd-tree says why it has no refit. Scene::
// update_vertices is tested in test_update_vertices.cpp.
#include "accel/bvh/bvh_build.h"
#include "accel/dispatch/kernel_entries.h"
#include "accel/factory/make_accel.h"
#include "accel/interface/inside.h"
#include "accel/wide/wide_refit.h"
#include "deform.h"
#include "engine/obj_loader.h"
#include "query_check.h"
#include "testing.h"

#include <doctest/doctest.h>
#include <tbb/task_arena.h>

#include <cstring>

using namespace arbor;
using namespace arbor::testing;

namespace {

struct Refittable {
    std::string name;
    accel::AccelKind kind;
    accel::BuildConfig cfg;
    std::unique_ptr<accel::Accel> accel;
};

/// Every BVH with both layouts (so every path) at every width this build traces, and brute.
std::vector<Refittable> refittable(const accel::TriangleView& v) {
    std::vector<Refittable> out;
    out.push_back({"brute", accel::AccelKind::brute, {}, accel::make_accel(accel::AccelKind::brute, v)});
    for (const accel::AccelKind kind : {accel::AccelKind::bvh_median, accel::AccelKind::bvh_sah, accel::AccelKind::lbvh})
        for (const std::uint32_t w : {4u, 8u, 16u}) {
            if (!accel::wide_width_supported(w)) continue;
            accel::BuildConfig cfg;
            cfg.layouts = accel::Layouts::all;
            cfg.wide.width = w;
            out.push_back({std::string(accel::to_string(kind)) + "/w" + std::to_string(w), kind, cfg, accel::make_accel(kind, v, cfg)});
        }
    return out;
}

/// `refit` answers every query on every path it offers bit for bit as `fresh` does.
void check_same(const accel::Accel& refit, const accel::Accel& fresh, const std::vector<accel::Ray>& rays,
                const std::vector<accel::Vec3f>& points, const accel::Bounds& bounds) {
    std::vector<accel::Hit> want(rays.size()), got(rays.size());
    fresh.trace(rays, want, {accel::Query::closest, accel::TracePath::scalar});
    std::vector<accel::Hit> want_any(rays.size());
    fresh.trace(rays, want_any, {accel::Query::any, accel::TracePath::scalar});
    for (const accel::TracePath path : {accel::TracePath::scalar, accel::TracePath::single, accel::TracePath::packet}) {
        if (!refit.offer().has(path)) continue;
        CAPTURE(accel::to_string(path));
        refit.trace(rays, got, {accel::Query::closest, path});
        std::size_t differ = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) differ += !same_hit(got[i], want[i]);
        CHECK(differ == 0);
        refit.trace(rays, got, {accel::Query::any, path});
        differ = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) differ += got[i].is_hit() != want_any[i].is_hit();
        CHECK(differ == 0);
    }
    const auto all_got = all_hits(refit, rays), all_want = all_hits(fresh, rays);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        bool same = all_got[i].size() == all_want[i].size();
        for (std::size_t k = 0; same && k < all_got[i].size(); ++k) same = same_hit(all_got[i][k], all_want[i][k]);
        differ += !same;
    }
    CHECK(differ == 0);
    std::vector<accel::PointHit> cp_got(points.size()), cp_want(points.size());
    refit.closest_points(points, INFINITY, cp_got);
    fresh.closest_points(points, INFINITY, cp_want);
    differ = 0;
    for (std::size_t i = 0; i < points.size(); ++i) differ += !same_point(cp_got[i], cp_want[i]);
    CHECK(differ == 0);
    std::vector<std::uint8_t> in_got(points.size()), in_want(points.size());
    accel::inside_points(refit, bounds, points, in_got);
    accel::inside_points(fresh, bounds, points, in_want);
    CHECK(in_got == in_want);
}

/// Every box of the scalar layout holds what it should: a leaf child's box its triangles, a node
/// child's box that node's two boxes; the root box everything.
std::string check_bvh2_boxes(const accel::Bvh2Layout& l) {
    const auto box = [](const accel::Bvh2Node& n, int c) {
        return accel::Bounds{{n.x[c], n.y[c], n.z[c]}, {n.x[2 + c], n.y[2 + c], n.z[2 + c]}};
    };
    for (std::size_t i = 0; i < l.nodes.size(); ++i) {
        const accel::Bvh2Node& n = l.nodes[i];
        for (int c = 0; c < 2; ++c) {
            if (!l.root_box.contains(box(n, c))) return "root box misses node " + std::to_string(i);
            if (n.is_leaf(c)) {
                for (std::uint32_t s = n.child[c]; s < n.child[c] + n.count[c]; ++s)
                    for (int k = 0; k < 3; ++k) {
                        const accel::Vec3f p = l.vertex(s, k);
                        if (!box(n, c).contains(accel::Bounds{p, p})) return "leaf of node " + std::to_string(i) + " misses slot " + std::to_string(s);
                    }
            } else {
                const accel::Bvh2Node& m = l.nodes[n.child[c]];
                if (!box(n, c).contains(box(m, 0)) || !box(n, c).contains(box(m, 1)))
                    return "node " + std::to_string(i) + " misses child node " + std::to_string(n.child[c]);
            }
        }
    }
    return {};
}

}  // namespace

TEST_CASE("refit: a deforming model, every BVH layout, width and path, bit for bit as fresh builds") {
    const engine::Mesh rest = testing::deforming_model();
    engine::Mesh mesh;
    deform(rest, mesh, 0);
    std::vector<Refittable> built = refittable(mesh.view());
    for (int step = 1; step <= 4; ++step) {
        CAPTURE(step);
        deform(rest, mesh, step);  // in place: the vectors keep their storage, as update_vertices does
        const std::vector<accel::Ray> rays = three_kinds(mesh.bounds, 256, 40u + std::uint32_t(step));
        // brute tests every triangle per ray: every eighth ray of each kind keeps it short.
        std::vector<accel::Ray> brute_rays;
        for (std::size_t i = 0; i < rays.size(); i += 8) brute_rays.push_back(rays[i]);
        const std::vector<accel::Vec3f> points = query_points(mesh, 48, 7u + std::uint32_t(step));
        for (Refittable& r : built) {
            CAPTURE(r.name);
            REQUIRE(r.accel->refit_unsupported().empty());
            const accel::RefitResult res = r.accel->refit(mesh.view());
            CHECK(res.sah_cost > 0.0);
            CHECK(res.built_sah_cost > 0.0);
            const auto fresh = accel::make_accel(r.kind, mesh.view(), r.cfg);
            check_same(*r.accel, *fresh, r.kind == accel::AccelKind::brute ? brute_rays : rays, points, mesh.bounds);
            if (const auto* bvh = dynamic_cast<const accel::BvhAccel*>(r.accel.get())) CHECK(check_bvh2_boxes(bvh->layout()) == "");
        }
    }
}

TEST_CASE("refit: positions unchanged keep the tree's SAH cost, a deformation raises it") {
    const engine::Mesh rest = testing::deforming_model();
    engine::Mesh mesh;
    for (const accel::AccelKind kind : {accel::AccelKind::bvh_sah, accel::AccelKind::lbvh}) {
        CAPTURE(accel::to_string(kind));
        deform(rest, mesh, 0);
        accel::BuildConfig cfg;
        cfg.layouts = accel::Layouts::simd;
        const auto a = accel::make_accel(kind, mesh.view(), cfg);
        // The build's boxes are exact unions already (a chunk of an oversized leaf may have had its
        // whole range's box: never smaller after the refit).
        const accel::RefitResult same = a->refit(mesh.view());
        CHECK(same.ratio() <= 1.0 + 1e-12);
        CHECK(same.ratio() > 0.99);
        deform(rest, mesh, 3, 0.2f);  // a much larger displacement: the old splits fit worse
        const accel::RefitResult moved = a->refit(mesh.view());
        CAPTURE(moved.sah_cost);
        CAPTURE(moved.built_sah_cost);
        CHECK(moved.ratio() > 1.05);
    }
}

TEST_CASE("refit: the same layouts on 1 and 2 threads") {
    const engine::Mesh rest = testing::deforming_model();
    engine::Mesh mesh;
    deform(rest, mesh, 0);
    accel::BvhBuildConfig bcfg;
    const accel::BinaryBvh bvh = accel::build_bvh_sah(accel::make_prim_refs(mesh.view()), bcfg);
    deform(rest, mesh, 3);
    accel::WideLayout<8> one = accel::make_wide_layout<8>(bvh, mesh.view());
    accel::WideLayout<8> two = accel::make_wide_layout<8>(bvh, mesh.view());
    double cost_one = 0.0, cost_two = 0.0;
    deform(rest, mesh, 5);
    tbb::task_arena(1).execute([&] { cost_one = accel::refit_wide_layout(one, mesh.view()); });
    tbb::task_arena(2).execute([&] { cost_two = accel::refit_wide_layout(two, mesh.view()); });
    CHECK(cost_one == cost_two);
    REQUIRE(one.nodes.size() == two.nodes.size());
    CHECK(std::memcmp(one.nodes.data(), two.nodes.data(), one.nodes.size() * sizeof(one.nodes[0])) == 0);
    CHECK(std::memcmp(one.blocks.data(), two.blocks.data(), one.blocks.size() * sizeof(one.blocks[0])) == 0);
    CHECK(std::memcmp(one.orders.data(), two.orders.data(), one.orders.size()) == 0);
    // Refitting a layout made over pose 3 to pose 5 gives the boxes a layout made over pose 5 from
    // the same binary tree would contain: every leaf box holds its triangles.
    for (const auto& node : one.nodes)
        for (std::size_t c = 0; c < node.children; ++c) {
            if (!node.is_leaf(c)) continue;
            const accel::Bounds box{node.boxes.lo(c), node.boxes.hi(c)};
            for (std::uint32_t s = node.child[c] * 8; s < node.child[c] * 8 + node.count[c]; ++s)
                if (one.prim(s) != accel::invalid_prim)
                    for (int k = 0; k < 3; ++k) CHECK(box.contains(accel::Bounds{one.vertex(s, k), one.vertex(s, k)}));
        }
}

TEST_CASE("refit: the kd-tree has none and says why") {
    const engine::Mesh m = procedural_shapes();
    for (const accel::Layouts layouts : {accel::Layouts::all, accel::Layouts::simd, accel::Layouts::scalar}) {
        accel::BuildConfig cfg;
        cfg.layouts = layouts;
        const auto kd = accel::make_accel(accel::AccelKind::kdtree, m.view(), cfg);
        CHECK(kd->refit_unsupported().find("split planes") != std::string_view::npos);
        CHECK_THROWS_AS(kd->refit(m.view()), std::logic_error);
    }
}
